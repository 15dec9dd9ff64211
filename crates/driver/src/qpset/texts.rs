//! The texts of a set: the qpbenchmark module, the README and the residual definitions.

use serde_json::{json, Value};

/// The set's Python module (qpbenchmark loads `NAME.py` and its class `NAME` in PascalCase).
pub const MODULE_FILE: &str = "signorini_contact.py";

/// The `qpbenchmark.TestSet` subclass the module defines.
pub const TEST_SET_CLASS: &str = "SignoriniContact";

/// The module: a `qpbenchmark.TestSet` reading `data/*.npz`, as `mpc_qpbenchmark.py` and
/// `maros_meszaros.py` do, runnable as `python signorini_contact.py run` or
/// `qpbenchmark signorini_contact.py run`.
pub fn module() -> String {
    r#"#!/usr/bin/env python3
# -*- coding: utf-8 -*-
#
# Written by `signorini qpset` (see README.md and metadata.json next to this file).

"""FEM contact test set: 2D elastic bodies in frictionless or Tresca contact.

Each problem is min 1/2 x'Px + q'x subject to Gx <= h, stored in data/NAME.npz as the CSC
arrays P_indptr, P_indices, P_data, P_shape (and G_...), the vectors q and h, and, when
signorini's reference solve succeeded, x_ref, z_ref (multipliers of Gx <= h) and objective_ref.
"""

import os
from typing import Iterator, Optional, Tuple

import numpy as np
import qpbenchmark
import scipy.sparse as spa
from qpbenchmark.benchmark import main


def _csc(data, key: str) -> spa.csc_matrix:
    shape = tuple(int(s) for s in data[f"{key}_shape"])
    return spa.csc_matrix(
        (
            data[f"{key}_data"].astype(float),
            data[f"{key}_indices"].astype(np.int32),
            data[f"{key}_indptr"].astype(np.int32),
        ),
        shape=shape,
    )


def load_problem(path: str) -> qpbenchmark.Problem:
    """Load one problem from its .npz file (named after the file)."""
    name = os.path.basename(path)[: -len(".npz")]
    with np.load(path, allow_pickle=False) as data:
        # Copies: some solvers (DAQP) refuse read-only inputs.
        return qpbenchmark.Problem(
            _csc(data, "P"),
            data["q"].copy(),
            _csc(data, "G"),
            data["h"].copy(),
            None,
            None,
            None,
            None,
            name=name,
        )


def load_reference(path: str) -> Optional[Tuple[np.ndarray, np.ndarray, float]]:
    """Reference (x, z, objective) of a problem, or None when it has none."""
    with np.load(path, allow_pickle=False) as data:
        if "x_ref" not in data.files:
            return None
        return data["x_ref"].copy(), data["z_ref"].copy(), float(data["objective_ref"])


class SignoriniContact(qpbenchmark.TestSet):
    """Contact problems of linear elasticity discretised by finite elements."""

    data_dir: str

    @property
    def description(self) -> str:
        """Description of the test set."""
        return (
            "2D FEM contact problems (frictionless and Tresca) from signorini: "
            "long interfaces, stiffness contrast, floating bodies (singular P), "
            "near-incompressibility, mortar and node-to-segment contact."
        )

    @property
    def title(self) -> str:
        """Test set title."""
        return "FEM contact test set (signorini)"

    @property
    def sparse_only(self) -> bool:
        """FEM matrices: sparse, and too large for dense solvers beyond the smallest."""
        return True

    def define_tolerances(self, runtime: float = 10.0) -> None:
        """qpbenchmark's tolerances, with the time limit from QPSET_RUNTIME (seconds) if set."""
        limit = os.environ.get("QPSET_RUNTIME", "")
        super().define_tolerances(runtime=float(limit) if limit else runtime)

    def __init__(self):
        """Initialize test set."""
        super().__init__()
        current_dir = os.path.dirname(os.path.abspath(__file__))
        self.data_dir = os.path.join(current_dir, "data")

    def __iter__(self) -> Iterator[qpbenchmark.Problem]:
        """Iterate over test set problems."""
        for fname in sorted(os.listdir(self.data_dir)):
            if fname.endswith(".npz"):
                yield load_problem(os.path.join(self.data_dir, fname))


if __name__ == "__main__":
    test_set_path = os.path.abspath(__file__)
    test_set_dir = os.path.dirname(test_set_path)
    main(
        test_set_path=test_set_path,
        results_path=f"{test_set_dir}/results/qpbenchmark_results.csv",
    )
"#
    .to_string()
}

/// Our residual definitions (docs/scene.md, "Residuals"), for `metadata.json`.
pub fn residual_definitions() -> Value {
    json!({
        "note": "signorini's KKT residuals of (x, z) on the contact QP before the auxiliary rewriting (P = A, q = -f, G = B, h = g, z = the contact forces lambda); scales local to each connected component, see docs/scene.md#residuals. qpbenchmark's own residuals (absolute: primal max(0, Gx - h), dual |Px + q + G'z|, duality gap) are computed by qpbenchmark itself.",
        "relative_penetration": "max_i max(0, (Gx - h)_i) / X~_i",
        "stationarity": "max_j |(Px + q + G'z)_j| / F~_j",
        "complementarity": "max_i |z_i (h - Gx)_i| / (F_c(i) X_i); a Tresca row adds |s_i |r_i| - z_i r_i| / (F_c(i) X_i)",
        "min_multiplier": "min_i min(0, z_i / F_c(i)); a Tresca row adds min(0, (s_i - |z_i|) / F_c(i))",
        "solved_when": "relative_penetration, stationarity, complementarity and -min_multiplier all <= the tolerance",
    })
}

/// The set's README.md.
pub fn readme(raw: bool, tol: f64, entries: &[Value]) -> String {
    let form = if raw {
        "in the scenes' own units (`--raw`)"
    } else {
        "nondimensionalised exactly as signorini's backends see them (A divided by its mean \
         diagonal, lengths by the displacement unit; `units` in metadata.json gives both)"
    };
    let mut s = format!(
        "# FEM contact test set for qpbenchmark\n\n\
         Written by `signorini qpset`. Each problem is\n\n\
         ```\nminimise 1/2 x'Px + q'x  subject to  Gx <= h\n```\n\n\
         with P = A (the stiffness matrix of the free displacements, symmetric, both triangles \
         stored; singular when a body is held by contact alone, `kernel` then holds its \
         rigid-body modes), q = -f (the loads), G = B (one row per contact constraint: the \
         normal gap's linearisation) and h = g (the initial gaps), {form}. Tresca friction's \
         box rows |z_i| <= s_i are rewritten with one auxiliary unknown t_i >= |r_i| per row \
         (objective term s_i t_i, rows r_i - t_i <= 0 and -r_i - t_i <= 0), so every row is \
         one-sided.\n\n\
         `data/NAME.npz` holds the CSC arrays `P_indptr`, `P_indices`, `P_data`, `P_shape` \
         (and `G_…`), `q`, `h`, and the reference `x_ref`, `z_ref`, `objective_ref` \
         (signorini's `auto` backend, status `solved` at relative KKT tolerance {tol:e}; \
         `metadata.json` names the backend `auto` chose and our residuals of the reference).\n\n\
         Run it: `pip install qpbenchmark` (and the solvers), then \
         `python signorini_contact.py run --settings high_accuracy` or \
         `qpbenchmark signorini_contact.py run`; results go to `results/`. The time limit per \
         solve is qpbenchmark's 10 s, or `QPSET_RUNTIME` seconds when that variable is set.\n\n\
         ## Problems\n\n| problem | kind | n | m | nnz(P) | reference objective |\n|---|---|---|---|---|---|\n"
    );
    for e in entries {
        let objective = e["reference"]["objective"]
            .as_f64()
            .map_or_else(|| "—".to_string(), |o| format!("{o:.9e}"));
        s.push_str(&format!(
            "| {} | {} | {} | {} | {} | {} |\n",
            e["name"].as_str().unwrap_or(""),
            e["kind"].as_str().unwrap_or(""),
            e["n"],
            e["m"],
            e["nnz_P"],
            objective
        ));
    }
    s.push_str(
        "\n## Residuals\n\nqpbenchmark measures its own absolute residuals. signorini judges an \
         answer by relative ones, with scales local to each connected component of the bodies \
         (docs/scene.md, \"Residuals\"); `metadata.json` (`residuals`) states them.\n",
    );
    s
}
