#!/usr/bin/env python3
"""Write the WPI RBE-2002 maze robot's logged run as a ring table and its layout.

    rbe2002_table.py ROBOTLOG_MAT OUT_PREFIX

ROBOTLOG_MAT is `Matlab/RobotLog.mat` of github.com/doates625/RBE-2002-Final-Project (commit
2b15a7b; no licence is stated, so the data stay out of this repository): 540 samples of a real
robot with four HC-SR04 sonars (front, back, left, right), its pose from wheel encoders and an
IMU heading, driving a maze of about 2.3 m by 2.3 m. The file holds MATLAB `RobotData`
objects; reading them takes the `mat-io` package (`pip install mat-io`).

Writes OUT_PREFIX.table.txt (`t x y heading r_front r_back r_left r_right`: metres, heading in
degrees counter-clockwise from +x, `-` where the robot marked a reading invalid) and
OUT_PREFIX.layout.json. Then:

    sonarmap convert OUT_PREFIX.table.txt --layout OUT_PREFIX.layout.json --out OUT_PREFIX.json

What the log holds and how it is turned (`RobotData.m` in the same folder):
- no clock was logged: sample k is placed at k seconds;
- `heading` is measured clockwise from +y (forward is (sin h, cos h)), so the table's heading
  is 90° − h;
- `sonarF/B/L/R` are each reading's absolute hit point, the range measured from the robot's
  centre (the firmware adds each sensor's distance from the centre, `RobotDims.cpp`: front
  0.0489 m, back 0.1284 m, left and right 0.1248 m). The range is recovered as the hit
  point's distance from `pos`, less that distance, and the layout mounts each sonar there;
- a reading is valid when it is non-zero and at most 0.75 m from the centre (`sXvalid`, the
  robot's own cut against floor bounces); an invalid one is written as no echo.
"""
import json
import math
import sys

# Distance of each sonar from the robot's centre along its axis (RobotDims.cpp), metres.
MOUNTS = [("F", 0.0489, 0.0), ("B", 0.1284, 180.0), ("L", 0.1248, 90.0), ("R", 0.1248, -90.0)]
# The robot's radius (RobotData.m's RADIUS 0.14 m is "approximate"; the side sonars sit at
# 0.125 m and the back one at 0.128 m).
RADIUS_M = 0.13


def scalar(value):
    return float(value.reshape(-1)[0])


def main():
    if len(sys.argv) != 3:
        sys.exit(__doc__)
    source, prefix = sys.argv[1], sys.argv[2]
    try:
        import matio
    except ImportError:
        sys.exit("rbe2002_table.py: reading MATLAB objects needs the mat-io package (pip install mat-io)")
    samples = matio.load_from_mat(source)["robotLog"]
    lines = [
        f"# {source}: WPI RBE-2002 maze robot, 4 HC-SR04; sample k at k s (no clock was logged)",
        "# t x y heading_deg r_front r_back r_left r_right (m; - = invalid)",
    ]
    for k in range(samples.shape[1]):
        p = samples[0, k].properties
        x, y = (float(v) for v in p["pos"].reshape(-1))
        heading_deg = math.degrees(math.pi / 2 - scalar(p["heading"]))
        heading_deg = (heading_deg + 180.0) % 360.0 - 180.0
        row = [f"{k}", f"{x:.6f}", f"{y:.6f}", f"{heading_deg:.4f}"]
        for name, offset_m, _ in MOUNTS:
            if not bool(p[f"s{name}valid"].reshape(-1)[0]):
                row.append("-")
                continue
            hx, hy = (float(v) for v in p[f"sonar{name}"].reshape(-1))
            row.append(f"{math.hypot(hx - x, hy - y) - offset_m:.4f}")
        lines.append(" ".join(row))
    with open(prefix + ".table.txt", "w") as out:
        out.write("\n".join(lines) + "\n")
    layout = {
        "format": "sonarmap-layout",
        "version": 1,
        "units": "m",
        "name": "WPI RBE-2002 maze robot: 4 HC-SR04 (front, back, left, right)",
        "robot": {
            "radius": RADIUS_M,
            "sonars": [
                {"x": round(offset_m * math.cos(math.radians(a)), 4),
                 "y": round(offset_m * math.sin(math.radians(a)), 4),
                 "heading_deg": a}
                for _, offset_m, a in MOUNTS
            ],
        },
        # HC-SR04: a 30° cone (the datasheet's 15° measuring angle either side); the robot's
        # own 0.75 m cut, less the front sonar's offset, bounds every valid range.
        "sensor": {"accuracy_pct": 1.0, "beam_width_deg": 30.0, "max_range": 0.75,
                   "min_range": 0.02},
    }
    with open(prefix + ".layout.json", "w") as out:
        json.dump(layout, out, indent=1)
        out.write("\n")
    print(f"{prefix}.table.txt: {samples.shape[1]} samples")


if __name__ == "__main__":
    main()
