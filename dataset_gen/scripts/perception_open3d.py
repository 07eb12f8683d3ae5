#!/usr/bin/env python3
"""Open3D's equivalent of the perception chain (spec rope_shovel.md §3), timed
per step on the same scan as `perceive`, for comparison with the Rust chain.

    perceive --pile typical --seed 1 --write-ply /tmp/typical.ply > /tmp/typical.json
    OMP_NUM_THREADS=1 python3 dataset_gen/scripts/perception_open3d.py /tmp/typical.ply /tmp/typical.json

The second argument is perceive's JSON output (its `config` gives the same
parameters, with the scan's roll, pitch and sensor position). Open3D has
the filters, the voxel grid and PCA normals; the bilateral smoothing and the
8 x 8 B-spline fit are numpy (vectorised) on Open3D's neighbour search.
Differences kept as Open3D has them: its radius filter counts the point
itself (so nb_points = n_min + 1 here) and its statistical filter drops only
the far side. Needs `pip install open3d` (not used by CI).
"""

import json
import sys
import time

import numpy as np
import open3d as o3d


def levelling_matrix(roll_deg, pitch_deg):
    a, b = np.radians(roll_deg), np.radians(pitch_deg)
    return np.array([
        [np.cos(b), 0.0, -np.sin(b)],
        [np.sin(a) * np.sin(b), np.cos(a), np.sin(a) * np.cos(b)],
        [np.cos(a) * np.sin(b), -np.sin(a), np.cos(a) * np.cos(b)],
    ])


def cubic_basis(t, lo, h):
    s = (t - lo) / h
    span = np.minimum(np.floor(s).astype(int), 4)
    u = s - span
    v = 1.0 - u
    w = np.stack([v ** 3 / 6, (3 * u ** 3 - 6 * u ** 2 + 4) / 6,
                  (-3 * u ** 3 + 3 * u ** 2 + 3 * u + 1) / 6, u ** 3 / 6], axis=1)
    return span, w


def main():
    ply_path, json_path = sys.argv[1], sys.argv[2]
    cfg = json.load(open(json_path))["config"]
    pcd = o3d.io.read_point_cloud(ply_path)
    times = {}
    t_all = time.perf_counter()

    t = time.perf_counter()
    lv = cfg["level"]
    pts = np.asarray(pcd.points) @ levelling_matrix(lv["roll_deg"], lv["pitch_deg"]).T + np.array(lv["sensor_position"])
    times["level"] = time.perf_counter() - t

    t = time.perf_counter()
    pt = cfg["pass_through"]
    keep = ((pts[:, 0] >= pt["x"][0]) & (pts[:, 0] <= pt["x"][1]) & (pts[:, 1] >= pt["y"][0])
            & (pts[:, 1] <= pt["y"][1]) & (pts[:, 2] >= pt["ground_height"]) & (pts[:, 2] <= pt["z_max"]))
    cloud = o3d.geometry.PointCloud(o3d.utility.Vector3dVector(pts[keep]))
    times["pass-through"] = time.perf_counter() - t

    t = time.perf_counter()
    cloud, _ = cloud.remove_radius_outlier(nb_points=cfg["radius"]["min_neighbours"] + 1,
                                           radius=cfg["radius"]["radius"])
    times["radius filter"] = time.perf_counter() - t

    t = time.perf_counter()
    cloud, _ = cloud.remove_statistical_outlier(nb_neighbors=cfg["statistical"]["k"],
                                                std_ratio=cfg["statistical"]["alpha"])
    times["statistical filter"] = time.perf_counter() - t

    t = time.perf_counter()
    cloud = cloud.voxel_down_sample(cfg["voxel"]["size"])
    times["voxel down-sampling"] = time.perf_counter() - t

    t = time.perf_counter()
    sm = cfg["smoothing"]
    cloud.estimate_normals(o3d.geometry.KDTreeSearchParamRadius(sm["radius"]))
    cloud.orient_normals_to_align_with_direction([0.0, 0.0, 1.0])
    p = np.asarray(cloud.points)
    n = np.asarray(cloud.normals)
    tree = o3d.geometry.KDTreeFlann(cloud)
    out = p.copy()
    two_sd2, two_sn2 = 2 * sm["sigma_distance"] ** 2, 2 * sm["sigma_normal"] ** 2
    for i in range(len(p)):
        _, idx, d2 = tree.search_radius_vector_3d(p[i], sm["radius"])
        idx = np.asarray(idx)
        h = (p[idx] - p[i]) @ n[i]
        w = np.exp(-np.asarray(d2) / two_sd2 - h * h / two_sn2)
        out[i] = p[i] + n[i] * (w @ h) / w.sum()
    times["bilateral smoothing"] = time.perf_counter() - t

    t = time.perf_counter()
    x, y, z = out[:, 0], out[:, 1], out[:, 2]
    x0, x1, y0, y1 = x.min(), x.max(), y.min(), y.max()
    jx, wx = cubic_basis(x, x0, (x1 - x0) / 5)
    ky, wy = cubic_basis(y, y0, (y1 - y0) / 5)
    a = np.zeros((len(z), 64))
    rows = np.arange(len(z))
    for i in range(4):
        for k in range(4):
            a[rows, (jx + i) * 8 + ky + k] += wx[:, i] * wy[:, k]
    c, *_ = np.linalg.lstsq(a, z, rcond=None)
    r2 = 1 - np.sum((z - a @ c) ** 2) / np.sum((z - z.mean()) ** 2)
    times["surface fit"] = time.perf_counter() - t

    total = time.perf_counter() - t_all
    print(json.dumps({"open3d": o3d.__version__, "points_in": len(pts), "points_fitted": len(z),
                      "r_squared": r2, "step_s": times, "total_s": total}, indent=2))


if __name__ == "__main__":
    main()
