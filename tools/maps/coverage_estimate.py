#!/usr/bin/env python3
"""An optimistic time for lane coverage of a map, to weigh the coverage goal against.

Lanes are laid per room, along x or along y (every choice of direction per room is tried, or
one with --along), evenly spaced at most --spacing apart from the room's first to its last column
(or row) where the robot's centre may stand: the free cells farther than --radius + --clearance
from every other cell. Two patterns are timed, each at its most favourable:

  u-turns   the lanes from end to end at --speed, and a U-turn between neighbouring lane
            segments that takes pi / --yaw-rate (a half turn at the yaw-rate limit, whatever its
            radius), with nothing for speeding up, slowing down or settling onto a lane;
  headland  the same lanes shortened by the tool's half width at each end, their U-turns over a
            pass along the lanes' ends (the spacing per end, at --speed) that sweeps what the
            U-turns leave, the pass's own corners free.

Both add --room-change-s per room after the first (a transit between rooms) and nothing for
moving between the pieces furniture splits a room into. The lower bound is the simulator's
(host_sim's CoverageScore): the free cells a centre --radius from the walls reaches with the
tool's half width, over tool width x speed. Coverage is what the straight lanes (and the
headland pass) sweep of that area, the U-turns' arcs left out.

Rooms are rectangles in world coordinates, name:x0,x1,y0,y1 [m]; the defaults are the shipped
house's (tools/maps/make_maps.py, house(), shifted by its start point).

  python3 tools/maps/coverage_estimate.py scenarios/maps/house.yaml
"""
import argparse
import itertools
import math
import os
import sys

HOUSE_ROOMS = [
    "living:-4.85,0.45,-4.1,-0.8",
    "kitchen:0.55,4.85,-4.1,-0.8",
    "hall:-4.85,4.85,-0.7,0.7",
    "bedroom1:-4.85,-1.05,0.8,3.6",
    "bathroom:-0.95,1.45,0.8,3.6",
    "bedroom2:1.55,4.85,0.8,3.6",
]


def fail(msg):
    sys.exit(f"coverage_estimate: {msg}")


def read_map(yaml_path):
    keys = {}
    if not os.path.isfile(yaml_path):
        fail(f"{yaml_path}: not found")
    with open(yaml_path) as f:
        for n, line in enumerate(f, 1):
            line = line.split("#", 1)[0].strip()
            if not line:
                continue
            if ":" not in line:
                fail(f"{yaml_path}:{n}: expected 'key: value'")
            k, v = line.split(":", 1)
            keys[k.strip()] = v.strip()
    for k in ("image", "resolution", "origin", "negate", "occupied_thresh", "free_thresh"):
        if k not in keys:
            fail(f"{yaml_path}: {k}: missing")
    res = float(keys["resolution"])
    origin = [float(x) for x in keys["origin"].strip("[]").split(",")]
    image = os.path.join(os.path.dirname(yaml_path), keys["image"])
    if not os.path.isfile(image):
        fail(f"{yaml_path}: image: {image}: not found")
    data = open(image, "rb").read()
    if data[:2] != b"P5":
        fail(f"{image}: expected a binary PGM (P5)")
    tok, i = [], 2
    while len(tok) < 3:
        while data[i : i + 1].isspace():
            i += 1
        if data[i : i + 1] == b"#":
            while data[i : i + 1] != b"\n":
                i += 1
            continue
        j = i
        while not data[j : j + 1].isspace():
            j += 1
        tok.append(int(data[i:j]))
        i = j
    w, h, maxval = tok
    px = data[i + 1 : i + 1 + w * h]
    if len(px) != w * h:
        fail(f"{image}: truncated")
    negate = int(keys["negate"])
    free_t = float(keys["free_thresh"])
    free = [[False] * w for _ in range(h)]
    for r in range(h):  # row 0 = lowest y, as map_server
        row = px[(h - 1 - r) * w : (h - r) * w]
        for c in range(w):
            p = row[c] / maxval if negate else (maxval - row[c]) / maxval
            free[r][c] = p < free_t
    return w, h, res, origin[0], origin[1], free


def disc(radius, res):
    k = int(math.ceil(radius / res)) + 1
    return [(dr, dc) for dr in range(-k, k + 1) for dc in range(-k, k + 1)
            if math.hypot(dr, dc) * res <= radius + 1e-9]


def erode(free, w, h, radius, res):
    """Free cells farther than radius from every cell that is not free and from the map's edge
    (centre to centre, as the simulator's score)."""
    offs = disc(radius, res)
    out = [[False] * w for _ in range(h)]
    for r in range(h):
        for c in range(w):
            if not free[r][c]:
                continue
            out[r][c] = all(0 <= r + dr < h and 0 <= c + dc < w and free[r + dr][c + dc]
                            for dr, dc in offs)
    return out


def widen(mask, free, w, h, radius, res):
    offs = disc(radius, res)
    out = [[False] * w for _ in range(h)]
    for r in range(h):
        for c in range(w):
            if mask[r][c]:
                for dr, dc in offs:
                    rr, cc = r + dr, c + dc
                    if 0 <= rr < h and 0 <= cc < w and free[rr][cc]:
                        out[rr][cc] = True
    return out


def reachable(mask, w, h, r0, c0):
    """The 4-connected part of mask that holds (r0, c0)."""
    if not (0 <= r0 < h and 0 <= c0 < w and mask[r0][c0]):
        fail("the start point is not where the robot's centre may stand")
    seen = [[False] * w for _ in range(h)]
    seen[r0][c0] = True
    stack = [(r0, c0)]
    while stack:
        r, c = stack.pop()
        for rr, cc in ((r - 1, c), (r + 1, c), (r, c - 1), (r, c + 1)):
            if 0 <= rr < h and 0 <= cc < w and mask[rr][cc] and not seen[rr][cc]:
                seen[rr][cc] = True
                stack.append((rr, cc))
    return seen


def runs(seq):
    out, start = [], None
    for i, a in enumerate(list(seq) + [False]):
        if a and start is None:
            start = i
        if not a and start is not None:
            out.append((start, i - 1))
            start = None
    return out


def lay_lanes(allowed, r0, r1, c0, c1, along_y, spacing, res):
    """Lane segments of a room: (fixed index, first, last) in grid cells, lanes along y when
    along_y (fixed = column), else along x (fixed = row)."""
    if along_y:
        fixed = [c for c in range(c0, c1 + 1) if any(allowed[r][c] for r in range(r0, r1 + 1))]
    else:
        fixed = [r for r in range(r0, r1 + 1) if any(allowed[r][c] for c in range(c0, c1 + 1))]
    if not fixed:
        return []
    a, b = fixed[0], fixed[-1]
    n = max(1, math.ceil((b - a) * res / spacing) + 1)
    segs = []
    for q in range(n):
        f = a + round(q * (b - a) / (n - 1)) if n > 1 else a
        if along_y:
            seq = [allowed[r][f] for r in range(r0, r1 + 1)]
            segs += [(f, r0 + s, r0 + e) for s, e in runs(seq)]
        else:
            seq = [allowed[f][c] for c in range(c0, c1 + 1)]
            segs += [(f, c0 + s, c0 + e) for s, e in runs(seq)]
    return segs


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("map", help="map YAML (map_server format)")
    ap.add_argument("--radius", type=float, default=0.171, help="robot radius [m]")
    ap.add_argument("--clearance", type=float, default=0.05, help="lanes' wall clearance [m]")
    ap.add_argument("--tool", type=float, default=0.342, help="tool width [m]")
    ap.add_argument("--spacing", type=float, default=0.308, help="largest lane spacing [m]")
    ap.add_argument("--speed", type=float, default=0.3, help="cruise speed [m/s]")
    ap.add_argument("--yaw-rate", type=float, default=1.9, help="yaw-rate limit [rad/s]")
    ap.add_argument("--room-change-s", type=float, default=5.0, help="per room change [s]")
    ap.add_argument("--start", type=float, nargs=2, default=(0.0, 0.0), help="start x y [m]")
    ap.add_argument("--room", action="append", help="name:x0,x1,y0,y1 [m] (repeat)")
    ap.add_argument("--target", type=float, default=0.95, help="coverage to reach [0, 1]")
    ap.add_argument("--along", choices=("best", "x", "y"), default="best",
                    help="lanes along x or y in every room, or the faster per room")
    a = ap.parse_args()
    rooms = []
    for spec in a.room or HOUSE_ROOMS:
        try:
            name, box = spec.split(":")
            x0, x1, y0, y1 = (float(v) for v in box.split(","))
        except ValueError:
            fail(f"--room {spec}: expected name:x0,x1,y0,y1")
        rooms.append((name, x0, x1, y0, y1))

    w, h, res, ox, oy, free = read_map(a.map)

    def cell(x, o):
        return int(math.floor((x - o) / res))

    sr, sc = cell(a.start[1], oy), cell(a.start[0], ox)
    centre = reachable(erode(free, w, h, a.radius, res), w, h, sr, sc)
    # The simulator's reach: half the tool less half a cell (a lane must pass over a cell's centre).
    area_mask = widen(centre, free, w, h, a.tool / 2 - res / 2, res)
    area = sum(map(sum, area_mask)) * res * res
    bound = area / (a.tool * a.speed)
    allowed = erode(free, w, h, a.radius + a.clearance, res)
    allowed = [[allowed[r][c] and centre[r][c] for c in range(w)] for r in range(h)]
    uturn = math.pi / a.yaw_rate
    half = a.tool / 2
    print(f"area {area:.2f} m^2, lower bound {bound:.1f} s; U-turn {uturn:.2f} s")

    # Each room in each direction: its figures and the cells its lanes (and pass) sweep.
    k = int(round(half / res))
    across = int(round(a.spacing / res / 2))
    plans = []
    for name, x0, x1, y0, y1 in rooms:
        c0, c1 = max(0, cell(x0, ox)), min(w - 1, cell(x1, ox))
        r0, r1 = max(0, cell(y0, oy)), min(h - 1, cell(y1, oy))
        options = []
        for along_y in {"best": (True, False), "x": (False,), "y": (True,)}[a.along]:
            segs = lay_lanes(allowed, r0, r1, c0, c1, along_y, a.spacing, res)
            o = {"room": name, "along": "y" if along_y else "x", "segs": len(segs),
                 "turns": max(0, len(segs) - 1), "lanes_m": 0.0, "short_m": 0.0,
                 "head_m": 0.0, "lane_cells": set(), "head_cells": set()}
            for f, s0, e0 in segs:
                o["lanes_m"] += (e0 - s0) * res
                o["short_m"] += max(0.0, (e0 - s0) * res - 2 * half)
                o["head_m"] += 2 * a.spacing
                for i in range(s0, e0 + 1):
                    for d in range(-k, k + 1):
                        rr, cc = (i, f + d) if along_y else (f + d, i)
                        if 0 <= rr < h and 0 <= cc < w and area_mask[rr][cc]:
                            o["lane_cells"].add(rr * w + cc)
                # The headland pass round each end: the tool's half width along the lane, the
                # spacing's stretch (and the half width) across it.
                for end in (s0, e0):
                    for i in range(end - k, end + k + 1):
                        for d in range(-k - across, k + across + 1):
                            rr, cc = (i, f + d) if along_y else (f + d, i)
                            if 0 <= rr < h and 0 <= cc < w and area_mask[rr][cc]:
                                o["head_cells"].add(rr * w + cc)
            o["t_u"] = o["lanes_m"] / a.speed + o["turns"] * uturn
            o["t_h"] = (o["short_m"] + o["head_m"]) / a.speed + o["turns"] * uturn
            options.append(o)
        plans.append(options)
    changes = max(0, len(rooms) - 1) * a.room_change_s
    cells_total = area / (res * res)

    def evaluate(choice, pattern):
        t = changes + sum(o["t_" + pattern] for o in choice)
        swept = set()
        for o in choice:
            swept |= o["lane_cells"]
            if pattern == "h":
                swept |= o["head_cells"]
        return t, len(swept) / cells_total

    print("| room | lanes along | segments | lanes [m] | time, u-turns [s] | time, headland [s] |")
    print("| --- | --- | --- | --- | --- | --- |")
    for options in plans:
        for o in options:
            print(f"| {o['room']} | {o['along']} | {o['segs']} | {o['lanes_m']:.1f} | "
                  f"{o['t_u']:.1f} | {o['t_h']:.1f} |")
    choices = list(itertools.product(*plans))
    fastest = min(choices, key=lambda ch: sum(o["t_u"] for o in ch))
    t, cov = evaluate(fastest, "u")
    print(f"u-turns, fastest directions ({''.join(o['along'] for o in fastest)}): {t:.1f} s = "
          f"{t / bound:.3f}x the lower bound; its straight lanes sweep {100 * cov:.1f} % (the "
          f"U-turns' arcs add to that, not counted here)")
    fastest = min(choices, key=lambda ch: sum(o["t_h"] for o in ch))
    t, cov = evaluate(fastest, "h")
    print(f"headland, fastest directions ({''.join(o['along'] for o in fastest)}): {t:.1f} s = "
          f"{t / bound:.3f}x the lower bound, sweeping {100 * cov:.1f} %")
    reaching = [(evaluate(ch, "h"), ch) for ch in choices]
    top = max(cov for (t, cov), ch in reaching)
    reaching = [(t, cov, ch) for (t, cov), ch in reaching if cov >= a.target]
    if reaching:
        t, cov, ch = min(reaching, key=lambda r: r[0])
        print(f"headland, fastest directions sweeping {100 * a.target:.0f} % or more "
              f"({''.join(o['along'] for o in ch)}): {t:.1f} s = {t / bound:.3f}x the lower bound, "
              f"sweeping {100 * cov:.1f} %")
    else:
        print(f"headland: no choice of directions sweeps {100 * a.target:.0f} % "
              f"(at most {100 * top:.1f} %)")

if __name__ == "__main__":
    main()
