#!/usr/bin/env python3
"""Write a QP  min 1/2 x'Ax - f'x  s.t.  Bx <= g  in the layout `signorini compare --qp DIR` reads.

Usage: python3 scripts/qp-from-scipy.py DIR      (needs numpy and scipy)

The example: 10 unit springs in series, the first tied to a support, the last pushed by a unit
force against a wall 5 away.  Its optimum is x_i = (i + 1)/2, contact force 1/2, objective -3.75.
Replace A, f, B, g with your own (A symmetric positive semidefinite, sparse; B one row per
constraint).  fixtures/qp/spring-chain/ was written by this script.
"""
import sys, pathlib
import numpy as np, scipy.io, scipy.sparse as sp

n = 10                                                   # A: n x n, symmetric PSD, sparse
A = sp.diags([-np.ones(n - 1), np.r_[2.0 * np.ones(n - 1), 1.0], -np.ones(n - 1)], [-1, 0, 1])
f = np.zeros((n, 1)); f[-1] = 1.0                       # vectors as n x 1 columns (mmwrite needs 2-D)
B = sp.coo_matrix(([1.0], ([0], [n - 1])), shape=(1, n))  # m x n, one row per constraint
g = np.array([[5.0]])                                    # m x 1
out = pathlib.Path(sys.argv[1] if len(sys.argv) > 1 else "qp"); out.mkdir(parents=True, exist_ok=True)
scipy.io.mmwrite(out / "A.mtx", A, symmetry="symmetric")  # writes the lower triangle
for name, M in [("f", f), ("B", B), ("g", g)]:
    scipy.io.mmwrite(out / f"{name}.mtx", M, symmetry="general")
