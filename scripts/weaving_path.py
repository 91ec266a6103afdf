#!/usr/bin/env python3
"""A plan whose robot weaves along each straight leg instead of driving it dead straight (issue 40).

    scripts/weaving_path.py PLAN OUT --amplitude-m A --period-m P [--seed S]

A teleoperated or wall-following robot does not hold its heading: it drifts off its line and
is steered back. Each leg of PLAN's path between two distinct positions becomes a sine of
amplitude A and period P (metres) about the leg, with a phase drawn from the seed, pulled
linearly back to the leg's ends so that the waypoints stay where they were. The heading follows
the weave (up to atan(2*pi*A/P) off the leg: 8.9 degrees at A = 0.1 m, P = 4 m). Legs that
turn on the spot are kept. Waypoints come every 0.2 m; `simulate --cycle-step-m` re-cuts them.

    scripts/weaving_path.py assets/pioneer_corridor.plan.json weave.plan.json \\
        --amplitude-m 0.05 --period-m 4 --seed 3
    sonarmap simulate weave.plan.json --out weave.json --seed 3 --drift mild \\
        --cycle-step-m 0.015 --cycle-s 0.3 --firing-groups 3
    sonarmap eval weave.json --plan weave.plan.json --preset extended --align

Lengths are in the plan's own units only when they are metres: the script refuses other units.
"""
import argparse, json, math, random

SPACING_M = 0.2


def weave_leg(a, b, amplitude, period, phase):
    """Waypoints (x, y, heading_deg) from a to b, a excluded, b included."""
    (ax, ay), (bx, by) = a[:2], b[:2]
    length = math.hypot(bx - ax, by - ay)
    ux, uy = (bx - ax) / length, (by - ay) / length
    along = math.atan2(uy, ux)
    at_start = amplitude * math.sin(phase)
    at_end = amplitude * math.sin(2 * math.pi * length / period + phase)

    def offset(s):
        return amplitude * math.sin(2 * math.pi * s / period + phase) - at_start * (1 - s / length) - at_end * s / length

    def slope(s):
        return amplitude * 2 * math.pi / period * math.cos(2 * math.pi * s / period + phase) + (at_start - at_end) / length

    n = max(1, round(length / SPACING_M))
    points = []
    for k in range(1, n + 1):
        s = length * k / n
        o = offset(s)
        heading = along + math.atan(slope(s))
        points.append([round(ax + ux * s - uy * o, 4), round(ay + uy * s + ux * o, 4), round(math.degrees(heading), 3)])
    return points


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("plan")
    parser.add_argument("out")
    parser.add_argument("--amplitude-m", type=float, required=True)
    parser.add_argument("--period-m", type=float, required=True)
    parser.add_argument("--seed", type=int, default=1)
    args = parser.parse_args()
    if args.amplitude_m < 0 or args.period_m <= 0:
        parser.error("the amplitude must be at least 0 and the period positive")
    with open(args.plan) as f:
        plan = json.load(f)
    if plan.get("units") != "m":
        parser.error(f"{args.plan}: units {plan.get('units')!r}, expected \"m\"")
    if plan.get("step") is not None or plan.get("turn_step_deg") is not None:
        parser.error(f"{args.plan}: waypoints with step/turn_step_deg; give a path of poses")
    rng = random.Random(f"weave-{args.seed}")
    path = plan["path"]
    woven = [list(path[0])]
    for a, b in zip(path, path[1:]):
        if math.hypot(b[0] - a[0], b[1] - a[1]) < 1e-9:
            woven.append(list(b))
            continue
        leg = weave_leg(a, b, args.amplitude_m, args.period_m, rng.uniform(0, 2 * math.pi))
        # The turn onto the leg happens on the spot at its start, as in the straight plan.
        woven.append([woven[-1][0], woven[-1][1], leg[0][2]])
        woven.extend(leg)
        woven[-1][2] = leg[-1][2]
    plan["path"] = woven
    plan["name"] = f"{plan.get('name', 'plan')} (weaving {args.amplitude_m} m every {args.period_m} m, seed {args.seed})"
    with open(args.out, "w") as f:
        json.dump(plan, f, indent=1)


if __name__ == "__main__":
    main()
