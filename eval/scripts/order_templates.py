#!/usr/bin/env python3
"""A template file of the nearest grown template of each dig-type sequence.

For the log entry "retry seeds of other dig orders" (2026-12-07): given a
task (REPORT:NAME, a task of an `eval learned` report.json; its task file
for `plan --task-file` is written beside OUT as OUT.task.json), the dig counts to take and
type sequences to leave out (D downward, B backward, in dig order), writes
the nearest template of each other sequence in artifacts/templates_grown.json,
nearest first, with task features scaled by their spread as
infer/src/sequence/nearest.rs scales them. Give it to
`plan --task-file OUT.task.json --retry-templates OUT`.

    python3 eval/scripts/order_templates.py runs/learned_s15/report.json:F25 2 DD OUT.json
"""
import json
import math
import sys

(report, name), counts, skip, out = sys.argv[1].rsplit(":", 1), sys.argv[2], sys.argv[3], sys.argv[4]
counts = {int(c) for c in counts.split(",")}
skip = set(skip.split(","))
library = json.load(open("artifacts/templates_grown.json"))
templates = library["templates"]


def features(t):
    return [t["length"], t["depth"], t["slope_far"], t["slope_near"], t["far_edge"]]


stored = [features(t["task"]) for t in templates]
lo = [min(f[i] for f in stored) for i in range(5)]
span = [max(max(f[i] for f in stored) - lo[i], 1e-6) for i in range(5)]
t = next(x["task"] for x in json.load(open(report))["tasks"] if x["name"] == name)
at = features(t)
json.dump({"length": t["length"], "depth": t["depth"], "slope_far_deg": math.degrees(t["slope_far"]),
           "slope_near_deg": math.degrees(t["slope_near"]), "far_edge": t["far_edge"]},
          open(out.removesuffix(".json") + ".task.json", "w"))
order = sorted(range(len(stored)), key=lambda k: math.dist(
    [a / s for a, s in zip(at, span)], [f / s for f, s in zip(stored[k], span)]))
nearest = {}
for k in order:
    digs = templates[k]["digs"]
    kinds = "".join("B" if d[0] >= 0.5 else "D" for d in digs)
    if len(digs) in counts and kinds not in skip and kinds not in nearest:
        nearest[kinds] = k
print(name, " ".join(nearest))
json.dump({"format": library["format"], "templates": [templates[k] for k in nearest.values()]},
          open(out, "w"))
