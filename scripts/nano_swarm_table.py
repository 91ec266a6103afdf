#!/usr/bin/env python3
"""Write one drone's run of ETH-PBL's Nano_Swarm_Mapping as a ring table that `sonarmap convert`
reads, with its sensor layout and, from the evaluation notebook, its floor plan.

    nano_swarm_table.py EXP_DIR DRONE OUT_PREFIX [--notebook NB --env NAME] [--step-s 5]

The data set (github.com/ETH-PBL/Nano_Swarm_Mapping, GPL-3.0; Friess et al., "Fully Onboard
SLAM for Distributed Mapping With a Swarm of Nano-Drones", IEEE IoT-J 2024) holds real flights
of Crazyflie 2.1 drones with four VL53L5CX time-of-flight sensors (front, back, left, right), one
row of 8 zones each, 5.625 degrees apart. `EXP_DIR` is one of its `evaluation/data/...`
directories:
  - `scans.csv`: `drone/keyframe,HEX`; the blob is a u16 keyframe id, 2 bytes of padding, then
    15 frames of 4 x 8 little-endian i16 ranges (mm, negative: no echo) followed by three f32,
    the frame's odometry offset from its keyframe (dx, dy in metres, dyaw in radians);
  - `poses.csv`: `drone/keyframe,x,y,yaw`, two rows a keyframe, the odometry's pose first (then
    the drone's own SLAM estimate, not used here);
  - `vicon_poses.csv`: the motion-capture pose of each keyframe (`id,x,y,z,qw,qx,qy,qz`).

Written:
  - OUT_PREFIX.table.txt: `t x y heading r_0 ... r_31`, metres and degrees, one line a frame, the
    odometry pose (keyframe pose plus the frame's offset). A zone's range is its depth (the
    sensor reports the distance along its axis) over the cosine of its bearing, so that the echo
    lies on the zone's own ray. Frames have no clock in the data: keyframe k is placed at
    k * step-s seconds and its frames 1/15 s apart (the sensors' rate);
  - OUT_PREFIX.layout.json: the 32 zones as sensors (`sonarmap-layout`), sensor d * 8 + c for
    direction d (front, back, left, right) and zone c, mounted 0.02 / 0.02 / 0.025 / 0.025 m out
    along their direction; a zone's echo lies on its axis (`"echo": "axis"`);
  - OUT_PREFIX.plan.json (with --notebook and --env): the walls of `NAME = Environment([Line(x1,
    y1, x2, y2), ...])` in the notebook, in the motion-capture frame, where the odometry starts,
    and the keyframes' motion-capture poses as its path;
  - OUT_PREFIX.truth.txt: the motion-capture pose of each keyframe, `t x y heading`.
"""
import argparse
import csv
import json
import math
import re
import struct

ZONE_STEP_DEG = 45.0 / 8
DIRECTIONS_DEG = [0.0, 180.0, 90.0, -90.0]
MOUNT_OFFSET_M = [0.02, 0.02, 0.025, 0.025]
FRAMES = 15
FRAME_BYTES = 76
FRAME_RATE_HZ = 15.0  # the sensors' rate: a burst's frames are placed this far apart


def bearing_deg(zone):
    return (3.5 - zone) * ZONE_STEP_DEG


def frames(blob):
    for i in range(FRAMES):
        frame = blob[4 + i * FRAME_BYTES : 4 + (i + 1) * FRAME_BYTES]
        ranges = struct.unpack("<32h", frame[:64])
        dx, dy, dyaw = struct.unpack("<3f", frame[64:])
        yield ranges, dx, dy, dyaw


def layout(name):
    sonars = []
    for d, base in enumerate(DIRECTIONS_DEG):
        off = MOUNT_OFFSET_M[d]
        for c in range(8):
            sonars.append({
                "x": round(off * math.cos(math.radians(base)), 6),
                "y": round(off * math.sin(math.radians(base)), 6),
                "heading_deg": base + bearing_deg(c),
            })
    return {
        "format": "sonarmap-layout", "version": 1, "units": "m", "name": name,
        "robot": {"radius": 0.05, "sonars": sonars},
        "sensor": {"max_range": 4.0, "min_range": 0.02, "beam_width_deg": ZONE_STEP_DEG,
                   "echo": "axis"},
    }


def walls_of(notebook, env):
    cells = json.load(open(notebook))["cells"]
    text = "".join("".join(c.get("source", [])) for c in cells)
    block = re.search(re.escape(env) + r"\s*=\s*Environment\(\[(.*?)\]\)", text, re.S)
    if not block:
        raise SystemExit(f"{notebook}: no `{env} = Environment([...])`")
    number = r"\s*(-?[0-9.]+)\s*"
    lines = re.findall(r"Line\(" + ",".join([number] * 4) + r"\)", block.group(1))
    return [[float(v) for v in line] for line in lines]


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("exp_dir")
    ap.add_argument("drone")
    ap.add_argument("out_prefix")
    ap.add_argument("--notebook")
    ap.add_argument("--env")
    ap.add_argument("--step-s", type=float, default=5.0)
    ap.add_argument("--poses", choices=["odometry", "truth"], default="odometry",
                    help="the keyframe poses of the table: the drone's odometry (default) or the motion capture's")
    a = ap.parse_args()
    odometry, truth, scans = {}, {}, {}
    for row in csv.reader(open(f"{a.exp_dir}/poses.csv")):
        odometry.setdefault(row[0], [float(v) for v in row[1:4]])  # the first row: odometry
    for row in csv.reader(open(f"{a.exp_dir}/vicon_poses.csv")):
        x, y, _z, w, qx, qy, qz = map(float, row[1:8])
        truth[row[0]] = (x, y, math.atan2(2 * (w * qz + qx * qy), 1 - 2 * (qy * qy + qz * qz)))
    for row in csv.reader(open(f"{a.exp_dir}/scans.csv")):
        if row[0].split("/")[0] == a.drone:
            scans[int(row[0].split("/")[1])] = bytes.fromhex(row[1])
    if not scans:
        raise SystemExit(f"{a.exp_dir}/scans.csv: no keyframe of drone {a.drone}")
    cos_bearing = [math.cos(math.radians(bearing_deg(c))) for c in range(8)] * 4
    path = []
    with open(a.out_prefix + ".table.txt", "w") as out, open(a.out_prefix + ".truth.txt", "w") as true_out:
        out.write(f"# {a.exp_dir}, drone {a.drone}: t x y heading (m, deg), then 32 zone ranges (m); - no echo\n")
        true_out.write("# t x y heading (m, deg): motion capture at each keyframe\n")
        for k in sorted(scans):
            key = f"{a.drone}/{k}"
            poses = odometry if a.poses == "odometry" else truth
            if key not in poses:
                source = "poses.csv" if a.poses == "odometry" else "vicon_poses.csv"
                raise SystemExit(f"{a.exp_dir}/{source}: no pose of keyframe {key}")
            x, y, yaw = poses[key]
            if key in truth:
                tx, ty, tyaw = truth[key]
                true_out.write(f"{k * a.step_s:.3f} {tx:.4f} {ty:.4f} {math.degrees(tyaw):.3f}\n")
                path.append([tx, ty, math.degrees(tyaw)])
            for i, (ranges, dx, dy, dyaw) in enumerate(frames(scans[k])):
                t = k * a.step_s + i / FRAME_RATE_HZ
                cells = ["-" if r < 0 else f"{r / 1000 / cos_bearing[s]:.4f}" for s, r in enumerate(ranges)]
                out.write(f"{t:.3f} {x + dx:.4f} {y + dy:.4f} {math.degrees(yaw + dyaw):.3f} " + " ".join(cells) + "\n")
    json.dump(layout(f"Crazyflie, 4 x VL53L5CX (8 zones each), {a.exp_dir}"), open(a.out_prefix + ".layout.json", "w"), indent=1)
    if a.notebook and a.env:
        plan = {"format": "sonarmap-plan", "version": 1, "units": "m",
                "name": f"{a.env} of {a.notebook}", "walls": walls_of(a.notebook, a.env),
                "path": path or [[0.0, 0.0, 0.0]]}
        json.dump(plan, open(a.out_prefix + ".plan.json", "w"), indent=1)


if __name__ == "__main__":
    main()
