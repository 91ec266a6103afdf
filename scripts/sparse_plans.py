#!/usr/bin/env python3
"""Plans of sparse lap runs, where most sonar readings find no echo (issue 41).

    scripts/sparse_plans.py [--seed S] [--count N] DIR

Writes DIR/FAMILY-SEED.plan.json (`sonarmap-plan` v1, inches; seeds S to S+N-1) for three
families, each a closed lap driven round and round by `bench --laps`:

- `openings`: a corridor 60 in wide with three 36 in openings into rooms on one side, its
  walls smooth (10-20 degrees of roughness): about two thirds of the readings find no echo.
- `hall`: a hall 1200 x 800 in, the lap 70-150 in from its walls: the far walls out of range.
- `outside`: a lap round the outside of a block on an open floor: the ring's outer half never
  echoes.

Each plan is drawn from its family and seed (Python's `random.Random` seeded with a string,
stable across versions): sizes, a turn of the whole scene, the walls' roughness (15-30 degrees
unless said), dropouts and ghosts. The plans give waypoints with
`step` and `turn_step_deg`, as the generated families do (8 in, 20 degrees). Make a log with
`sonarmap simulate PLAN --out LOG --seed 1`, or with MRPT's simulator along the same poses
(`peer.py sim PLAN --poses-from LOG --out LOG2`). These families are not in `eval --suite`, so
the suite's scenes and the figures measured on them stay as they are.
"""
import argparse, json, math, os, random

CORRIDOR_WIDTH_IN = 60.0
OPENING_IN = 36.0
HALL_IN = (1200.0, 800.0)


def polygon(corners):
    return [[*corners[i], *corners[(i + 1) % len(corners)]] for i in range(len(corners))]


def openings(rng):
    """A corridor along x, closed at both ends, rooms above it, each entered by an opening."""
    w = CORRIDOR_WIDTH_IN
    room_w, room_d, gap = rng.uniform(120, 180), rng.uniform(100, 180), rng.uniform(60, 120)
    length = 3 * room_w + 2 * gap + rng.uniform(100, 200)
    x0 = (length - 3 * room_w - 2 * gap) / 2
    walls = [[0, 0, length, 0], [length, 0, length, w], [0, w, 0, 0]]
    x = 0.0
    for i in range(3):
        a = x0 + i * (room_w + gap)
        b = a + room_w
        door = (a + b) / 2 - OPENING_IN / 2
        walls += [[x, w, door, w], [a, w, a, w + room_d], [a, w + room_d, b, w + room_d], [b, w + room_d, b, w]]
        x = door + OPENING_IN
    walls.append([x, w, length, w])
    return walls, [(40, w / 2), (length - 40, w / 2)], rng.uniform(10, 20)


def hall(rng):
    """An empty hall; the lap a rectangle `margin` in from the walls."""
    (w, h), m = HALL_IN, rng.uniform(70, 150)
    lap = [(m, m), (w - m, m), (w - m, h - m), (m, h - m)]
    return polygon([(0, 0), (w, 0), (w, h), (0, h)]), lap, rng.uniform(15, 30)


def outside(rng):
    """A block on an open floor, the lap round it anticlockwise `gap` in from its walls."""
    w, h, g = rng.uniform(200, 400), rng.uniform(150, 300), rng.uniform(30, 50)
    lap = [(-g, -g), (w + g, -g), (w + g, h + g), (-g, h + g)]
    return polygon([(0, 0), (w, 0), (w, h), (0, h)]), lap, rng.uniform(15, 30)


FAMILIES = {"openings": openings, "hall": hall, "outside": outside}


def plan(family, seed):
    rng = random.Random(f"{family}-{seed}")
    walls, lap, roughness_deg = FAMILIES[family](rng)
    turn = rng.uniform(0, 2 * math.pi)
    c, s = math.cos(turn), math.sin(turn)
    place = lambda x, y: (round(x * c - y * s, 3), round(x * s + y * c, 3))
    walls = [[*place(*w[:2]), *place(*w[2:])] for w in walls]
    lap = [place(*p) for p in lap]
    path = []
    for a, b in zip(lap, lap[1:] + lap[:1]):
        heading = round(math.degrees(math.atan2(b[1] - a[1], b[0] - a[0])), 3)
        path += [[*a, heading], [*b, heading]]
    path.append(path[0])
    return {"format": "sonarmap-plan", "version": 1, "units": "in",
            "name": f"{family} (sparse, seed {seed})", "note": __doc__.splitlines()[0],
            "walls": walls, "path": path, "step": 8, "turn_step_deg": 20,
            "roughness_deg": round(roughness_deg, 2),
            "sim": {"dropout": round(rng.uniform(0, 0.05), 3), "ghost": round(rng.uniform(0, 0.03), 3),
                    "ray_step_deg": 2.5}}


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--seed", type=int, default=1, help="seed of the first plan of each family")
    ap.add_argument("--count", type=int, default=1, help="plans of each family")
    ap.add_argument("dir")
    args = ap.parse_args()
    os.makedirs(args.dir, exist_ok=True)
    for family in FAMILIES:
        for seed in range(args.seed, args.seed + args.count):
            path = os.path.join(args.dir, f"{family}-{seed}.plan.json")
            with open(path, "w") as f:
                json.dump(plan(family, seed), f)
            print(path)


if __name__ == "__main__":
    main()
