#!/usr/bin/env python3
"""Writes exact mirror-image meshes of a `hertz-scene.py --mirror` scene as MSH 4.1 files.

The mesher need not mesh a mirrored polygon as the mirror image of the original's mesh, and on
the two-cylinder scene that difference is what is left of the normal-tangential coupling: the
press alone locks in a tangential traction (2.2 % of mu p0 with the two polygons meshed
separately, 0.5 % with mirrored meshes; BENCHMARKS.md, Cattaneo).  This takes the `lower`
body's mesh (body_id 1) from an ASCII solution.vtu of that scene (`signorini solve SCENE --vtu
ascii`) and writes it as DIR/lower.msh and its mirror image about y = BASE as DIR/upper.msh
(linear triangles, no physical groups: region boxes still select the nodes).  The scene then
names them with `mesh = "lower.msh"` and `mesh = "upper.msh"` instead of polygons.
crates/driver/tests/mirror/mod.rs builds the same meshes in Rust at test time (the lower slab
meshed through the library), so the tests need neither this script nor committed meshes.

Usage: python3 scripts/mirror-mesh.py SOLUTION.vtu BASE DIR
"""

import re
import sys


def arrays(path):
    """The VTU's ASCII DataArrays by name (the second one of a name, cell data, as NAME_cell)."""
    text = open(path).read()
    out = {}
    for m in re.finditer(r'<DataArray[^>]*Name="([^"]+)"[^>]*>(.*?)</DataArray>', text, re.S):
        key = m.group(1) if m.group(1) not in out else m.group(1) + "_cell"
        out[key] = m.group(2).split()
    return out


def write(path, pts, cells, f):
    """MSH 4.1 ASCII: one surface entity, the nodes `cells` use (mapped by `f`), the triangles."""
    used = sorted({v for c in cells for v in c})
    idx = {v: i + 1 for i, v in enumerate(used)}
    n, m = len(used), len(cells)
    with open(path, "w") as w:
        w.write("$MeshFormat\n4.1 0 8\n$EndMeshFormat\n")
        w.write("$Entities\n0 0 1 0\n1 0 0 0 2 2 0 0 0\n$EndEntities\n")
        w.write(f"$Nodes\n1 {n} 1 {n}\n2 1 0 {n}\n")
        w.writelines(f"{idx[v]}\n" for v in used)
        for v in used:
            x, y = f(pts[v])
            w.write(f"{x!r} {y!r} 0\n")
        w.write("$EndNodes\n")
        w.write(f"$Elements\n1 {m} 1 {m}\n2 1 2 {m}\n")
        for i, c in enumerate(cells):
            w.write(f"{i + 1} " + " ".join(str(idx[v]) for v in c) + "\n")
        w.write("$EndElements\n")


def main():
    """Reads the VTU and writes the two meshes."""
    a = arrays(sys.argv[1])
    base = float(sys.argv[2])
    coords = a["Points"]
    pts = [(float(coords[3 * i]), float(coords[3 * i + 1])) for i in range(len(coords) // 3)]
    conn = list(map(int, a["connectivity"]))
    offsets = list(map(int, a["offsets"]))
    cell_body = list(map(int, a["body_id_cell"]))
    cells, start = [], 0
    for k, end in enumerate(offsets):
        if cell_body[k] == 1:
            cells.append(conn[start:end])
        start = end
    write(sys.argv[3] + "/lower.msh", pts, cells, lambda p: p)
    write(sys.argv[3] + "/upper.msh", pts, cells, lambda p: (p[0], 2 * base - p[1]))
    print(len({v for c in cells for v in c}), "nodes,", len(cells), "triangles per body")


if __name__ == "__main__":
    main()
