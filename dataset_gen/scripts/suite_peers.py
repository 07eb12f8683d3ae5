"""Established optimisers on the project's standard suite, for `test-problem --suite`.

Runs pyswarms' GlobalBestPSO (its documented options c1 0.5, c2 0.3, w 0.9)
and mealpy's OriginalGWO on Sphere, Rosenbrock, Rastrigin and Ackley in 10
and 30 dimensions, on the bounds of `src/testfns.rs`, at population 50 x 100
iterations, over seeds 1..=51, and writes the median and quartiles of the
best value found as JSON (dataset_gen/scripts/suite_peers.json).

    python3 -m venv /tmp/peers && /tmp/peers/bin/pip install pyswarms==1.3.0 mealpy==3.0.3 numpy
    /tmp/peers/bin/python dataset_gen/scripts/suite_peers.py > dataset_gen/scripts/suite_peers.json
"""

import json
import logging
import sys

import numpy as np

logging.disable(logging.CRITICAL)

import pyswarms as ps  # noqa: E402
from mealpy import FloatVar, GWO  # noqa: E402

POPULATION, ITERATIONS, SEEDS = 50, 100, range(1, 52)
BOUNDS = {"sphere": 100.0, "rosenbrock": 30.0, "rastrigin": 5.12, "ackley": 32.0}


def f(name, x):
    x = np.asarray(x, dtype=float)
    if name == "sphere":
        return float(np.sum(x * x))
    if name == "rosenbrock":
        return float(np.sum(100.0 * (x[1:] - x[:-1] ** 2) ** 2 + (1.0 - x[:-1]) ** 2))
    if name == "rastrigin":
        return float(10.0 * len(x) + np.sum(x * x - 10.0 * np.cos(2 * np.pi * x)))
    n = len(x)
    return float(-20.0 * np.exp(-0.2 * np.sqrt(np.sum(x * x) / n))
                 - np.exp(np.sum(np.cos(2 * np.pi * x)) / n) + 20.0 + np.e)


def pyswarms_best(name, dim, seed):
    np.random.seed(seed)
    b = BOUNDS[name]
    opt = ps.single.GlobalBestPSO(
        n_particles=POPULATION, dimensions=dim,
        options={"c1": 0.5, "c2": 0.3, "w": 0.9},
        bounds=(np.full(dim, -b), np.full(dim, b)))
    cost, _ = opt.optimize(lambda X: np.array([f(name, r) for r in X]),
                           iters=ITERATIONS, verbose=False)
    return cost


def mealpy_gwo_best(name, dim, seed):
    b = BOUNDS[name]
    problem = {"obj_func": lambda x: f(name, x),
               "bounds": FloatVar(lb=[-b] * dim, ub=[b] * dim),
               "minmax": "min", "log_to": None}
    model = GWO.OriginalGWO(epoch=ITERATIONS, pop_size=POPULATION)
    return model.solve(problem, seed=seed).target.fitness


def stats(values):
    q1, med, q3 = np.percentile(values, [25, 50, 75])
    return {"median": med, "q1": q1, "q3": q3, "runs": len(values)}


out = []
for name in BOUNDS:
    for dim in (10, 30):
        for peer, run in (("pyswarms GlobalBestPSO", pyswarms_best),
                          ("mealpy OriginalGWO", mealpy_gwo_best)):
            vals = [run(name, dim, s) for s in SEEDS]
            out.append({"peer": peer, "problem": f"{name}-{dim}", **stats(vals)})
            print(out[-1], file=sys.stderr)
json.dump({"population": POPULATION, "iterations": ITERATIONS, "results": out},
          sys.stdout, indent=1)
