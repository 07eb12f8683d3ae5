"""Reference outputs of the crawler's preview-deviation fuzzy controller
(shared/spec/crawler.md §4) from scikit-fuzzy, for infer/tests/crawler_fuzzy.rs.

The same rule base as infer::crawler::fuzzy: universes e in [-0.45, 0.45] m,
ec in [-30, 30], u in [-2700, 2700] rpm; seven evenly spaced triangular sets
each (NB..PB), the outermost open-ended (shoulders); min for "and" and the
implication, max aggregation, centroid output.

scikit-fuzzy samples the universes; the output universe is sampled every
0.05 rpm, and the centroid of the sampled aggregate (skfuzzy integrates its
piecewise-linear interpolation) differs from the exact centroid only where a
kink of the aggregate falls between two samples.

Run (about 2 min): pip install scikit-fuzzy==0.5.0 numpy==2.4.6 scipy==1.17.1 networkx packaging
     python3 fuzzy_reference.py > fuzzy_reference.csv
"""
import numpy as np
import skfuzzy as fuzz
from skfuzzy import control as ctrl

LABELS = ["NB", "NM", "NS", "ZE", "PS", "PM", "PB"]
RULES = [  # rows ec, columns e
    ["NB", "NB", "NM", "NM", "NS", "NS", "ZE"],
    ["NB", "NM", "NM", "NS", "NS", "ZE", "PS"],
    ["NM", "NM", "NS", "NS", "ZE", "PS", "PS"],
    ["NM", "NS", "NS", "ZE", "PS", "PS", "PM"],
    ["NS", "NS", "ZE", "PS", "PS", "PM", "PM"],
    ["NS", "ZE", "PS", "PS", "PM", "PM", "PB"],
    ["ZE", "PS", "PS", "PM", "PM", "PB", "PB"],
]


def sets(var, half):
    w = half / 3.0
    u = var.universe
    for i, name in enumerate(LABELS):
        c = -half + i * w
        if i == 0:
            var[name] = fuzz.trapmf(u, [-half - 1, -half - 1, c, c + w])
        elif i == 6:
            var[name] = fuzz.trapmf(u, [c - w, c, half + 1, half + 1])
        else:
            var[name] = fuzz.trimf(u, [c - w, c, c + w])


e = ctrl.Antecedent(np.round(np.arange(-450, 451) * 0.001, 6), "e")
ec = ctrl.Antecedent(np.round(np.arange(-300, 301) * 0.1, 6), "ec")
u = ctrl.Consequent(np.round(np.arange(-54000, 54001) * 0.05, 6), "u", defuzzify_method="centroid")
sets(e, 0.45)
sets(ec, 30.0)
sets(u, 2700.0)
rules = [
    ctrl.Rule(ec[LABELS[r]] & e[LABELS[c]], u[RULES[r][c]])
    for r in range(7)
    for c in range(7)
]
sim = ctrl.ControlSystemSimulation(ctrl.ControlSystem(rules))

rng = np.random.default_rng(20261203)
grid = [(a, b) for a in np.linspace(-0.45, 0.45, 13) for b in np.linspace(-30, 30, 13)]
rand = list(zip(np.round(rng.uniform(-0.45, 0.45, 200), 4), np.round(rng.uniform(-30, 30, 200), 2)))
print("e,ec,u")
for a, b in grid + rand:
    sim.input["e"] = float(a)
    sim.input["ec"] = float(b)
    sim.compute()
    print(f"{float(a):.6f},{float(b):.6f},{sim.output['u']:.6f}")
