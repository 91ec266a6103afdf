#!/usr/bin/env python3
"""sonarmap's engine beside MRPT's occupancy-grid insertion, on the same lap runs, in one run.

    scripts/vs_mrpt.py --peer PATH/peer.py --laps N LOG [LOG ...]

For each LOG, `sonarmap bench LOG --laps N --preset all --engine-only` measures both presets (trace
off and on) and writes the lap run it measured; MRPT's peer then inserts that same run into a
5 cm occupancy grid (`peer.py grid`, insertion alone timed). One after another, never at once, so
no two timings share a core. Prints a Markdown table and the JSON lines it was made from.

Needs a release build (`cargo build --release`) and the MRPT peer (a harness around Debian's
libmrpt-maps-dev, which `sonarmap`'s own tests never need): `--peer` is its `peer.py`.
"""
import argparse, json, os, subprocess, sys, tempfile

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
SONARMAP = os.path.join(ROOT, "target", "release", "sonarmap")


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--peer", required=True, help="MRPT's peer.py")
    ap.add_argument("--laps", type=int, default=20000, help="snapshots of each lap run")
    ap.add_argument("--repeats", type=int, default=3)
    ap.add_argument("--sonarmap", default=os.environ.get("SONARMAP", SONARMAP))
    ap.add_argument("logs", nargs="+")
    args = ap.parse_args()
    rows, raw = [], []
    with tempfile.TemporaryDirectory() as tmp:
        for log in args.logs:
            lapped = os.path.join(tmp, "laps.json")
            out = subprocess.run(
                [args.sonarmap, "bench", log, "--laps", str(args.laps), "--preset", "all", "--engine-only",
                 "--repeats", str(args.repeats), "--write-log", lapped],
                check=True, capture_output=True, text=True).stdout
            lines = [json.loads(l) for l in out.splitlines() if l.strip()]
            mrpt = json.loads(subprocess.run([sys.executable, args.peer, "grid", lapped], check=True,
                                             capture_output=True, text=True).stdout)
            raw += lines + [dict(mrpt, log=log)]
            by = {l["preset"]: l for l in lines}
            rows.append((log, by["paper"], by["extended"], mrpt["snapshots_per_s"]))
    print(f"| log ({args.laps} snapshots) | paper /s | extended /s | extended trace on /s | MRPT grid /s | extended / MRPT | paper segments | extended segments |")
    print("| --- | --- | --- | --- | --- | --- | --- | --- |")
    for log, p, e, m in rows:
        print(f"| {os.path.basename(log)} | {p['engine_snapshots_per_s_trace_off']:,.0f} | {e['engine_snapshots_per_s_trace_off']:,.0f} "
              f"| {e['engine_snapshots_per_s_trace_on']:,.0f} | {m:,.0f} | {e['engine_snapshots_per_s_trace_off'] / m:.2f} "
              f"| {p['final_segments']:,} | {e['final_segments']:,} |")
    print()
    for r in raw:
        print(json.dumps(r))


if __name__ == "__main__":
    main()
