#!/usr/bin/env python3
"""Generates the blade case's FE matrices: a cantilevered steel plate ("blade") meshed with
8-node trilinear hexahedra, clamped at its root, written as Matrix Market K.mtx and M.mtx
(symmetric, lower triangle) next to this script. numpy only.

usage: python3 cases/blade/make_blade.py [--nx 128 --ny 50 --nz 4] [--out DIR]

Geometry and units (SI): span L = 0.2 m along x (root x = 0 clamped: its nodes are removed),
chord 0.08 m along y, thickness 0.006 m along z. Steel: E = 210 GPa, ν = 0.3,
ρ = 7800 kg/m³. Consistent mass (∫ρNᵀN, 2×2×2 Gauss, exact for trilinear products), full
2×2×2 integration of the stiffness. Every element is the same box, so the element matrices
are computed once and scattered. Fully integrated trilinear hexahedra are stiff in bending
(shear locking); with near-cubic elements and 4 through the thickness the first bending
frequency comes out a few percent above the plate's (printed for comparison with the
Euler–Bernoulli beam value), which does not matter for a benchmark of the reduction.

DOF numbering: node (i, j, k), i = 1..nx along the span, j = 0..ny along the chord, k = 0..nz
through the thickness; free node index n = ((i − 1)(ny + 1) + j)(nz + 1) + k, DOF 3n + d
(d = 0, 1, 2 for x, y, z). The DOFs the case uses are written to dofs.json (name -> index).
The default mesh has 97 920 DOFs; generation takes about 10-20 s, mostly the text output.
"""

import argparse
import json
import os
import time

import numpy as np

SPAN, CHORD, THICKNESS = 0.2, 0.08, 0.006  # m
YOUNG, POISSON, DENSITY = 210e9, 0.3, 7800.0  # Pa, -, kg/m³


def hex8_matrices(a, b, c):
    """Stiffness and consistent mass (24 × 24, DOF order node-major x, y, z) of an a×b×c box."""
    lam = YOUNG * POISSON / ((1 + POISSON) * (1 - 2 * POISSON))
    mu = YOUNG / (2 * (1 + POISSON))
    d = np.zeros((6, 6))
    d[:3, :3] = lam
    d[np.arange(3), np.arange(3)] += 2 * mu
    d[3:, 3:] = mu * np.eye(3)
    corners = np.array([[-1, -1, -1], [1, -1, -1], [1, 1, -1], [-1, 1, -1],
                        [-1, -1, 1], [1, -1, 1], [1, 1, 1], [-1, 1, 1]], dtype=float)
    g = 1 / np.sqrt(3)
    half = np.array([a, b, c]) / 2
    det = half.prod()
    k = np.zeros((24, 24))
    m = np.zeros((24, 24))
    for gp in corners * g:
        n = (1 + corners[:, 0] * gp[0]) * (1 + corners[:, 1] * gp[1]) * (1 + corners[:, 2] * gp[2]) / 8
        dn = np.empty((8, 3))  # dN/dx, physical
        for axis in range(3):
            others = [o for o in range(3) if o != axis]
            dn[:, axis] = (corners[:, axis] / 8 * (1 + corners[:, others[0]] * gp[others[0]])
                           * (1 + corners[:, others[1]] * gp[others[1]])) / half[axis]
        bmat = np.zeros((6, 24))
        bmat[0, 0::3] = dn[:, 0]
        bmat[1, 1::3] = dn[:, 1]
        bmat[2, 2::3] = dn[:, 2]
        bmat[3, 0::3], bmat[3, 1::3] = dn[:, 1], dn[:, 0]  # γ_xy
        bmat[4, 1::3], bmat[4, 2::3] = dn[:, 2], dn[:, 1]  # γ_yz
        bmat[5, 0::3], bmat[5, 2::3] = dn[:, 2], dn[:, 0]  # γ_xz
        k += bmat.T @ d @ bmat * det
        nn = np.kron(np.outer(n, n), np.eye(3))
        m += DENSITY * nn * det
    return k, m


def assemble(nx, ny, nz, ke, me):
    """Lower-triangle COO (rows, cols, K values, M values) of the clamped model, summed."""
    nodes_x, nodes_y, nodes_z = nx + 1, ny + 1, nz + 1
    i, j, k = np.meshgrid(np.arange(nx), np.arange(ny), np.arange(nz), indexing="ij")
    i, j, k = i.ravel(), j.ravel(), k.ravel()
    offsets = [(0, 0, 0), (1, 0, 0), (1, 1, 0), (0, 1, 0), (0, 0, 1), (1, 0, 1), (1, 1, 1), (0, 1, 1)]
    # Local corner order (x, y, z signs) matches hex8_matrices' `corners`.
    node = np.stack([((i + di) * nodes_y + (j + dj)) * nodes_z + (k + dk) for di, dj, dk in offsets],
                    axis=1)
    root = nodes_y * nodes_z  # nodes at i = 0 are clamped: free index = node − root
    dofs = (3 * (node - root))[:, :, None] + np.arange(3)[None, None, :]
    dofs = dofs.reshape(len(node), 24)  # −ve for clamped DOFs
    r = np.repeat(dofs, 24, axis=1).ravel()
    c = np.tile(dofs, (1, 24)).ravel()
    kv = np.tile(ke.ravel(), len(node))
    mv = np.tile(me.ravel(), len(node))
    keep = (r >= 0) & (c >= 0) & (r >= c)
    r, c, kv, mv = r[keep], c[keep], kv[keep], mv[keep]
    n = 3 * (nodes_x - 1) * nodes_y * nodes_z
    key = r.astype(np.int64) * n + c
    unique, inverse = np.unique(key, return_inverse=True)
    ksum = np.bincount(inverse, weights=kv)
    msum = np.bincount(inverse, weights=mv)
    return n, unique // n, unique % n, ksum, msum


def write_mtx(path, n, rows, cols, values):
    """Matrix Market coordinate real symmetric (lower triangle), 1-based, 17 digits."""
    keep = values != 0.0
    rows, cols, values = rows[keep] + 1, cols[keep] + 1, values[keep]
    with open(path, "w") as f:
        f.write("%%MatrixMarket matrix coordinate real symmetric\n")
        f.write("%% blade FE model (cases/blade/make_blade.py), SI units\n")
        f.write(f"{n} {n} {len(values)}\n")
        chunk = 200000  # one %-format per chunk: far faster than numpy.savetxt's row loop
        for s in range(0, len(values), chunk):
            e = min(s + chunk, len(values))
            items = np.empty((e - s, 3), dtype=object)
            items[:, 0], items[:, 1], items[:, 2] = rows[s:e].tolist(), cols[s:e].tolist(), values[s:e].tolist()
            f.write(("%d %d %.17g\n" * (e - s)) % tuple(items.ravel()))


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--nx", type=int, default=128)
    parser.add_argument("--ny", type=int, default=50)
    parser.add_argument("--nz", type=int, default=4)
    parser.add_argument("--out", default=os.path.dirname(os.path.abspath(__file__)))
    args = parser.parse_args()
    start = time.time()
    nx, ny, nz = args.nx, args.ny, args.nz
    ke, me = hex8_matrices(SPAN / nx, CHORD / ny, THICKNESS / nz)
    n, rows, cols, kv, mv = assemble(nx, ny, nz, ke, me)
    os.makedirs(args.out, exist_ok=True)
    write_mtx(os.path.join(args.out, "K.mtx"), n, rows, cols, kv)
    write_mtx(os.path.join(args.out, "M.mtx"), n, rows, cols, mv)

    def dof(i, j, k, d):
        return 3 * (((i - 1) * (ny + 1) + j) * (nz + 1) + k) + d

    # Ten contact nodes on the tip's upper edge (k = nz), evenly along the chord, z direction;
    # the forcing and the mid-chord output also in z at the tip.
    names = {f"tip{p}_z": dof(nx, round(p * ny / 9), nz, 2) for p in range(10)}
    names["force_z"] = dof(nx, ny // 2, 0, 2)  # mid-chord, lower face: no torsion forced
    with open(os.path.join(args.out, "dofs.json"), "w") as f:
        json.dump({"num_dofs": n, "mesh": [nx, ny, nz], "dofs": names}, f, indent=1)
    # Euler–Bernoulli cantilever for comparison: ω₁ = 1.875² √(EI / (ρA)) / L².
    beam = 1.875 ** 2 * np.sqrt(YOUNG * THICKNESS ** 2 / 12 / DENSITY) / SPAN ** 2
    print(f"make_blade: {n} DOFs, {len(kv)} stored entries per matrix, "
          f"{time.time() - start:.1f} s; Euler-Bernoulli first bending {beam:.1f} rad/s")


if __name__ == "__main__":
    main()
