"""Writes the Matrix Market matrices of cases/two_rods: two clamped FE rods facing each other.

Rod A (clamped at x = 0, 10 elements, L = 0.13 m) and rod B (clamped at its far end,
8 elements, L = 0.10 m), both A = 15.6 cm², E = 210 GPa, ρ = 7500 kg/m³, consistent linear
elements. DOFs: a1..a10 (a10 = A's free end), then b1..b8 (b1 = B's free end, facing a10).
Run: /usr/bin/python3 cases/two_rods/make_matrices.py (the .mtx files are committed).
"""
import os

E, AREA, RHO = 210e9, 15.6e-4, 7500.0


def rod(n, length):
    """Stiffness and mass of a rod clamped at node 0 with free end at node n (n×n)."""
    h = length / n
    k = [[0.0] * n for _ in range(n)]
    m = [[0.0] * n for _ in range(n)]
    for e in range(n):  # element between nodes e and e + 1; node 0 is clamped
        for i, a in ((0, e - 1), (1, e)):
            for j, b in ((0, e - 1), (1, e)):
                if a < 0 or b < 0:
                    continue
                k[a][b] += E * AREA / h * (1 if i == j else -1)
                m[a][b] += RHO * AREA * h / 6 * (2 if i == j else 1)
    return k, m


def write(path, blocks, size):
    entries = [(r, c, v) for r, c, v in blocks if v != 0.0]
    with open(path, "w") as out:
        out.write("%%MatrixMarket matrix coordinate real general\n")
        out.write(f"{size} {size} {len(entries)}\n")
        for r, c, v in entries:
            out.write(f"{r + 1} {c + 1} {v:.17g}\n")


ka, ma = rod(10, 0.13)
kb, mb = rod(8, 0.10)
# B is numbered from its free end: reverse its node order.
kb = [row[::-1] for row in kb[::-1]]
mb = [row[::-1] for row in mb[::-1]]
size = 18
here = os.path.dirname(os.path.abspath(__file__))
for name, a, b in (("K", ka, kb), ("M", ma, mb)):
    entries = [(i, j, a[i][j]) for i in range(10) for j in range(10)]
    entries += [(10 + i, 10 + j, b[i][j]) for i in range(8) for j in range(8)]
    write(os.path.join(here, f"{name}.mtx"), entries, size)
