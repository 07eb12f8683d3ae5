"""Length-only TSP reference for the roadheader's cutting paths.

Reads the instances that `roadheader report` writes
(artifacts/roadheader/points_<name>.json), solves the open path with
elkai (LKH-3) and writes artifacts/roadheader/tsp_elkai.json, which the
report quotes. The open path from the outermost plane becomes a tour
through a dummy node joined at cost 0 to the outermost plane's points and
at cost BIG to the rest; a move between non-adjacent points (more than one
grid step in some joint) also costs BIG, so a tour of cost < BIG breaks
no rule. Costs are integers in units of 10 µm (LKH multiplies them by
its precision 100 and needs the products in 32 bits).

    pip install elkai==2.0.1
    python3 dataset_gen/scripts/roadheader_tsp.py [artifacts/roadheader]
"""

import json
import math
import sys
from pathlib import Path

import elkai

BIG = 10**7


def solve(points):
    pos, cells, start = points["positions"], points["cells"], points["is_start"]
    n = len(pos)
    adjacent = lambda i, j: i != j and all(abs(a - b) <= 1 for a, b in zip(cells[i], cells[j]))
    m = [[0] * (n + 1) for _ in range(n + 1)]
    for i in range(n):
        m[0][i + 1] = m[i + 1][0] = 0 if start[i] else BIG
        for j in range(n):
            if i != j:
                m[i + 1][j + 1] = round(math.dist(pos[i], pos[j]) * 1e5) if adjacent(i, j) else BIG
    tour = elkai.DistanceMatrix(m).solve_tsp(runs=10)
    k = tour.index(0)
    order = [v - 1 for v in tour[k + 1:] + tour[:k] if v != 0]
    if not start[order[0]]:
        order.reverse()
    moves = list(zip(order, order[1:]))
    length = sum(math.dist(pos[a], pos[b]) for a, b in moves)
    turning = 0.0
    for (a, b), (_, c) in zip(moves, moves[1:]):
        u = [y - x for x, y in zip(cells[a], cells[b])]
        v = [y - x for x, y in zip(cells[b], cells[c])]
        cos = sum(x * y for x, y in zip(u, v)) / (math.hypot(*u) * math.hypot(*v))
        turning += math.degrees(math.acos(max(-1.0, min(1.0, cos))))
    return {
        "points": n,
        "length_m": length,
        "turning_deg": turning,
        "breaks_adjacency": sum(not adjacent(a, b) for a, b in moves),
        "starts_on_outermost_plane": bool(start[order[0]]),
    }


def main():
    root = Path(sys.argv[1] if len(sys.argv) > 1 else "artifacts/roadheader")
    table = {"solver": f"elkai {elkai.__version__ if hasattr(elkai, '__version__') else '2.0.1'} (LKH-3), runs=10"}
    for f in sorted(root.glob("points_*.json")):
        name = f.stem.removeprefix("points_")
        table[name] = solve(json.loads(f.read_text()))
        print(name, table[name])
    (root / "tsp_elkai.json").write_text(json.dumps(table, indent=2) + "\n")


if __name__ == "__main__":
    main()
