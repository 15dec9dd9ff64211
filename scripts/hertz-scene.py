#!/usr/bin/env python3
"""Writes the Hertz line-contact scene of fixtures/accuracy/ (hertz.toml, hertz-graded.toml).

An elastic cylinder (radius R, only a cap of height H modelled, its flat top loaded by a total
force P per unit length and held sideways) pressed onto an elastic block (W x D, clamped at its
base), both E, nu, plane strain.  Johnson, Contact Mechanics (1985), sec. 4.2, eqs. (4.43)-(4.45)
for two cylinders with parallel axes (the block is a cylinder of infinite radius):

    1/E* = (1 - nu1^2)/E1 + (1 - nu2^2)/E2          (= 2 (1 - nu^2) / E for equal bodies)
    a    = sqrt(4 P R / (pi E*))                     half-width of the contact strip
    p0   = 2 P / (pi a)          (= a E* / (2 R))    peak pressure,  p(x) = p0 sqrt(1 - x^2/a^2)

P is chosen for the requested a: P = pi a^2 E* / (4 R).

The arc is a polygon: vertices every `--arc-fine` along the arc for |x - cx| <= `--fine-width`
(so that the polygon's sag s^2 / (8R) is negligible against the gap a^2 / (2R) at x = a),
every `--arc-coarse` beyond.  Polygon vertices are kept by the mesher, so the arc spacing near
the contact is also the finest boundary spacing a mesh of this scene can have.

With `--cattaneo MU` the scene is Cattaneo-Mindlin partial slip instead (Johnson 1985, sec.
7.1, in 2-D): the cap's top is moved rigidly, first down by `--press` (named support `press`),
then sideways by `--shift` (`shift`) over `--increments` increments, with Coulomb friction MU on
the pair (mortar, the flat block as slave); the [reference] states R, E* and MU, and a, p0 and
the stick half-width c = a sqrt(1 - Q/(MU P)) follow from the run's forces P and Q.

With `--mirror` the block is replaced by the cap's mirror image about the contact line y = D:
two equal cylinders (Johnson 1985, sec. 4.2: 1/R* = 1/R + 1/R = 2/R, E* as above), named
`upper` (its flat top loaded, pressed or shifted as above) and `lower` (its flat bottom
clamped), each of height H, with the same arc polygon and mirrored refine boxes.  The mirror
keeps u_x and flips u_y, so for bodies of the same material the pressure gives both surfaces
the same u_x and a tangential traction both the same u_y: the normal and tangential problems
decouple exactly (up to the two meshes' interiors, which the mesher need not mirror), as
Cattaneo's theory assumes for half-spaces.  a, p0 and c then take R* = R/2 (the [reference]'s
`radius`).  The lower body is the slave (mortar).

Usage: python3 scripts/hertz-scene.py [--graded] [--cattaneo MU] [--mirror] [options] > scene.toml
"""

import argparse
import math
import sys


def arc_angles(r, phi0, fine_width, ds_fine, ds_coarse):
    """Angles from -phi0 to phi0: step ds_fine/R where |R sin(phi)| <= fine_width, else coarse."""
    phi_f = math.asin(min(1.0, fine_width / r))
    if phi_f >= phi0:
        n = max(1, math.ceil(2 * phi0 * r / ds_fine))
        return [-phi0 + 2 * phi0 * i / n for i in range(n + 1)]
    n_f = max(1, math.ceil(2 * phi_f * r / ds_fine))
    n_c = max(1, math.ceil((phi0 - phi_f) * r / ds_coarse))
    left = [-phi0 + (phi0 - phi_f) * i / n_c for i in range(n_c)]
    mid = [-phi_f + 2 * phi_f * i / n_f for i in range(n_f + 1)]
    right = [phi_f + (phi0 - phi_f) * i / n_c for i in range(1, n_c + 1)]
    return left + mid + right


def num(x):
    """A coordinate as TOML, rounded to 12 decimals (0.7, not 0.7000000000000001)."""
    return repr(round(x, 12))


def main():
    p = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    p.add_argument("--radius", type=float, default=1.0)
    p.add_argument("--half-width", type=float, default=0.05, help="Hertz a")
    p.add_argument("--young", type=float, default=1.0)
    p.add_argument("--poisson", type=float, default=0.3)
    p.add_argument("--block-width", type=float, default=1.6)
    p.add_argument("--block-depth", type=float, default=0.8)
    p.add_argument("--cap-height", type=float, default=0.6)
    p.add_argument("--hmax", type=float, default=0.01)
    p.add_argument("--arc-fine", type=float, default=0.00125)
    p.add_argument("--arc-coarse", type=float, default=0.02)
    p.add_argument("--fine-width", type=float, default=0.15)
    p.add_argument("--graded", action="store_true", help="add [[body.refine]] around the contact")
    p.add_argument("--zone", type=float, default=0.1, help="refine box half-width (graded)")
    p.add_argument("--zone-hmax", type=float, default=0.0025, help="refine hmax (graded)")
    p.add_argument("--formulation", default="mortar")
    p.add_argument("--title", default=None)
    p.add_argument("--cattaneo", type=float, default=None, metavar="MU",
                   help="Cattaneo-Mindlin: press, then shift, with Coulomb friction MU")
    p.add_argument("--press", type=float, default=0.002, help="Cattaneo: the top's downward move")
    p.add_argument("--shift", type=float, default=0.0005, help="Cattaneo: the top's sideways move")
    p.add_argument("--increments", type=int, default=2, help="Cattaneo: increments of the shift")
    p.add_argument("--mirror", action="store_true",
                   help="two equal cylinders: the block replaced by the cap's mirror image")
    a = p.parse_args()
    if a.mirror:
        mirror_main(a)
        return

    r, aa, e, nu = a.radius, a.half_width, a.young, a.poisson
    e_star = e / (2 * (1 - nu * nu))
    load = math.pi * aa * aa * e_star / (4 * r)
    p0 = 2 * load / (math.pi * aa)
    w, d, hc = a.block_width, a.block_depth, a.cap_height
    cx, base = w / 2, d
    top = base + hc
    centre_y = base + r
    phi0 = math.acos((r - hc) / r)
    angles = arc_angles(r, phi0, a.fine_width, a.arc_fine, a.arc_coarse)
    arc = [(cx + r * math.sin(t), centre_y - r * math.cos(t)) for t in angles]
    # Exact ends on the top line (cos(phi0) = (R - H)/R).
    xl, xr = arc[0][0], arc[-1][0]
    arc[0] = (xl, top)
    arc[-1] = (xr, top)
    polygon = ", ".join(f"[{x!r}, {y!r}]" for x, y in arc)
    traction = -load / (xr - xl)
    mesh = 'graded' if a.graded else 'uniform'
    title = a.title or (
        f"Hertz cylinder on a block ({mesh} mesh): a = {aa}, R = {r}"
        if a.cattaneo is None
        else f"Cattaneo-Mindlin, a cylinder pressed then shifted on a block ({mesh} mesh): "
        f"mu = {a.cattaneo}, R = {r}"
    )
    z = a.zone
    out = []
    out.append(f"# Generated by `python3 scripts/hertz-scene.py {' '.join(sys.argv[1:])}` (rerun it, do not edit by hand).")
    out.append("#")
    out.append(f"# Hertz line contact (Johnson 1985, sec. 4.2): cylinder R = {r} (cap of height {hc}) on a block")
    out.append(f"# {w} x {d} clamped at its base; both E = {e}, nu = {nu}, plane strain.")
    out.append(f"#   E* = E / (2 (1 - nu^2))          = {e_star!r}")
    if a.cattaneo is None:
        out.append(f"#   P  = pi a^2 E* / (4 R)            = {load!r}   (total force per unit length, for a = {aa})")
        out.append(f"#   a  = sqrt(4 P R / (pi E*))        = {aa!r}")
        out.append(f"#   p0 = 2 P / (pi a) = a E* / (2 R)  = {p0!r}")
        out.append(f"# The load is a uniform traction P / {xr - xl!r} on the cap's flat top (width {xr - xl!r}).")
    else:
        out.append("#   a  = sqrt(4 P R / (pi E*)),  p0 = 2 P / (pi a),  c = a sqrt(1 - Q / (mu P)),")
        out.append("#   q(x) = mu p0 / a (sqrt(a^2 - x^2) - sqrt(c^2 - x^2)) for |x| < c, mu p(x) for c < |x| < a,")
        out.append("# with P and Q the forces the run transmits (the study reads them from the result): the cap's")
        out.append(f"# top is moved rigidly, down by {a.press} (`press`), then sideways by {a.shift} (`shift`, in")
        out.append(f"# {a.increments} increments); Coulomb mu = {a.cattaneo}.  Elastically similar bodies: normal and")
        out.append("# tangential problems do not couple for half-spaces (Dundurs' beta = 0); these finite bodies'")
        out.append("# different lateral expansion under the press locks in a small tangential traction, odd in x.")
    if a.cattaneo is None:
        out.append(f"# The block is {d / aa:g} a deep and the cap {hc / aa:g} a high: Hertz assumes half-spaces, and the")
        out.append("# finite bodies shift a by O((a/depth)^2).  Measured (node-to-segment, uniform hmax = a/10): the")
        out.append("# 0.8 x 0.4 block with a 0.3 cap of crates/driver/tests/contact_verification.rs gives an a 0.4 %")
        out.append("# larger than the 1.6 x 0.8 block with a 0.6 cap; doubling again (3.2 x 1.6 block, half-disc cap;")
        out.append("# mortar, graded, arc vertices at the zone's hmax) moves a by 0.001 % (BENCHMARKS.md, issue 21).")
    out.append(f"# Arc: polygon vertices every {a.arc_fine} for |x - {cx}| <= {a.fine_width} (sag {a.arc_fine ** 2 / (8 * r):.2e},")
    out.append(f"# {a.arc_fine ** 2 / (8 * r) / (aa * aa / (2 * r)) * 100:.3f} % of the gap a^2/2R at x = a), every {a.arc_coarse} beyond.")
    out.append("")
    out.append(f"title = {title!r}".replace("'", '"'))
    out.append("")
    out.append("[[body]]")
    out.append('name = "cap"')
    out.append(f"polygon = [{polygon}]")
    out.append(f"hmax = {a.hmax!r}")
    out.append(f"young = {e!r}")
    out.append(f"poisson = {nu!r}")
    if a.graded:
        out.append("[[body.refine]]")
        out.append(f"region = [{num(cx - z)}, {num(cx + z)}, {num(base)}, {num(base + z)}]")
        out.append(f"hmax = {a.zone_hmax!r}")
    out.append("")
    out.append("[[body]]")
    out.append('name = "block"')
    out.append(f"polygon = [[0.0, 0.0], [{w!r}, 0.0], [{w!r}, {d!r}], [0.0, {d!r}]]")
    out.append(f"hmax = {a.hmax!r}")
    out.append(f"young = {e!r}")
    out.append(f"poisson = {nu!r}")
    if a.graded:
        out.append("[[body.refine]]")
        out.append(f"region = [{num(cx - z)}, {num(cx + z)}, {num(base - z)}, {num(base)}]")
        out.append(f"hmax = {a.zone_hmax!r}")
    out.append("")
    out.append("[[dirichlet]]")
    out.append('body = "block"')
    out.append(f"region = [0.0, {w!r}, 0.0, 0.0]")
    out.append("")
    if a.cattaneo is None:
        out.append("[[dirichlet]]")
        out.append('body = "cap"')
        out.append(f"region = [{xl!r}, {xr!r}, {top!r}, {top!r}]")
        out.append('components = ["x"]')
        out.append("")
        out.append("[[neumann]]")
        out.append('body = "cap"')
        out.append(f"region = [{xl!r}, {xr!r}, {top!r}, {top!r}]")
        out.append(f"traction = [0.0, {traction!r}]")
        out.append("")
    else:
        for name, comp, value in (("press", "y", [0.0, -a.press]), ("shift", "x", [a.shift, 0.0])):
            out.append("[[dirichlet]]")
            out.append(f'name = "{name}"')
            out.append('body = "cap"')
            out.append(f"region = [{xl!r}, {xr!r}, {top!r}, {top!r}]")
            out.append(f'components = ["{comp}"]')
            out.append(f"value = [{value[0]!r}, {value[1]!r}]")
            out.append("")
    out.append("[[contact]]")
    out.append('bodies = ["cap", "block"]')
    out.append(f"region = [{num(cx - 0.2)}, {num(cx + 0.2)}, {num(base - 0.01)}, {num(base + 0.03)}]")
    out.append(f'slave = "{"cap" if a.cattaneo is None else "block"}"')
    out.append(f'formulation = "{a.formulation}"')
    if a.cattaneo is not None:
        out.append(f"friction = {a.cattaneo!r}")
    out.append("")
    if a.cattaneo is not None:
        out.append("[[step]]")
        out.append("loads = { press = 1.0 }")
        out.append("")
        out.append("[[step]]")
        out.append("loads = { press = 1.0, shift = 1.0 }")
        out.append(f"increments = {a.increments}")
        out.append("")
    out.append("[reference]")
    out.append(f"centre = [{cx!r}, {base!r}]")
    if a.cattaneo is None:
        out.append(f"half_width = {aa!r}")
        out.append(f"peak_pressure = {p0!r}")
    else:
        out.append(f"radius = {r!r}")
        out.append(f"contact_modulus = {e_star!r}")
        out.append(f"friction = {a.cattaneo!r}")
    print("\n".join(out))


def mirror_header(a, geo, e_star, rs, load, p0):
    """The comment block of the two-cylinder scene (`--mirror`)."""
    aa, r, w, d = a.half_width, a.radius, a.block_width, a.block_depth
    out = [
        f"# Generated by `python3 scripts/hertz-scene.py {' '.join(sys.argv[1:])}` (rerun it, do not edit by hand).",
        "#",
        f"# Hertz line contact of two equal cylinders (Johnson 1985, sec. 4.2): R1 = R2 = R = {r}, each",
        f"# modelled as a {w} x {d} slab whose contact face is an arc of the cylinder (sag {geo['sag']:.2e}),",
        f"# mirror images about the contact line y = {geo['base']}: `upper` (its flat top moved or loaded)",
        f"# and `lower` (its flat bottom clamped); both E = {a.young}, nu = {a.poisson}, plane strain.",
        f"#   1/R* = 1/R1 + 1/R2 = 2/R            R* = {rs!r}",
        f"#   1/E* = 2 (1 - nu^2) / E             E* = {e_star!r}",
    ]
    if a.cattaneo is None:
        out += [
            f"#   P  = pi a^2 E* / (4 R*)             = {load!r}   (force per unit length, for a = {aa})",
            f"#   a  = sqrt(4 P R* / (pi E*))         = {aa!r}",
            f"#   p0 = 2 P / (pi a) = a E* / (2 R*)   = {p0!r}",
            f"# The load is a uniform traction P / {w!r} on the upper slab's flat top.",
        ]
    else:
        out += [
            "#   a  = sqrt(4 P R* / (pi E*)),  p0 = 2 P / (pi a),  c = a sqrt(1 - Q / (mu P)),",
            "#   q(x) = mu p0 / a (sqrt(a^2 - x^2) - sqrt(c^2 - x^2)) for |x| < c, mu p(x) for c < |x| < a",
            "# (Johnson 1985, sec. 7.1, in 2-D), P and Q the forces the run transmits (the study reads",
            f"# them from the result): the upper slab's top is moved rigidly, down by {a.press} (`press`),",
            f"# then sideways by {a.shift} (`shift`, in {a.increments} increments); Coulomb mu = {a.cattaneo}.",
        ]
    out += [
        f"# Mirror symmetry about y = {geo['base']} keeps u_x and flips u_y: for bodies of one material",
        "# the pressure gives both surfaces the same u_x (no relative slip) and a tangential traction",
        "# both the same u_y (no change of gap), so the normal and tangential problems decouple, as",
        "# Cattaneo's theory assumes of half-spaces (a cylinder on a block does not: the two expand",
        "# sideways differently under the press).  Not exactly: the meshes' interiors need not be",
        "# mirror images, and the rows act along the slave's reference normals, tilted by x/R from",
        "# the contact line's, which mixes p x/R into q: (x/R)/mu of mu p, hence a large R.",
        f"# Arc: polygon vertices every {a.arc_fine} for |x - {geo['cx']}| <= {a.fine_width} (sag {a.arc_fine ** 2 / (8 * r):.2e},",
        f"# {a.arc_fine ** 2 / (8 * r) / (aa * aa / (2 * rs)) * 100:.3f} % of the gap a^2/2R* at x = a = {aa}), every {a.arc_coarse} beyond.",
        "",
    ]
    return out


def mirror_body(name, polygon, a, refine):
    """A [[body]] table: the `polygon` (counter-clockwise) and the refine box `refine`."""
    text = ", ".join(f"[{x!r}, {y!r}]" for x, y in polygon)
    out = ["[[body]]", f'name = "{name}"', f"polygon = [{text}]", f"hmax = {a.hmax!r}",
           f"young = {a.young!r}", f"poisson = {a.poisson!r}"]
    if a.graded:
        out += ["[[body.refine]]", f"region = [{', '.join(num(v) for v in refine)}]",
                f"hmax = {a.zone_hmax!r}"]
    return out + [""]


def mirror_geometry(a):
    """The two slabs' polygons (counter-clockwise) and the points the scene names."""
    r, w, d = a.radius, a.block_width, a.block_depth
    cx, base = w / 2, d
    phi0 = math.asin(min(1.0, w / (2 * r)))
    angles = arc_angles(r, phi0, a.fine_width, a.arc_fine, a.arc_coarse)
    arc = [(cx + r * math.sin(t), base + r - r * math.cos(t)) for t in angles]
    arc[0], arc[-1] = (0.0, arc[0][1]), (w, arc[-1][1])
    top, bottom = 2 * d, 0.0
    upper = [(0.0, top)] + arc + [(w, top)]
    # The mirror image about y = base, reversed to stay counter-clockwise.
    lower = [(x, 2 * base - y) for x, y in reversed(upper)]
    lower[0], lower[-1] = (w, bottom), (0.0, bottom)
    return {"cx": cx, "base": base, "top": top, "bottom": bottom, "upper": upper,
            "lower": lower, "sag": arc[0][1] - base}


def mirror_main(a):
    """`--mirror`: two equal cylinders, mirror images about the contact line."""
    r, aa, w = a.radius, a.half_width, a.block_width
    e_star = a.young / (2 * (1 - a.poisson ** 2))
    rs = r / 2
    load = math.pi * aa * aa * e_star / (4 * rs)
    p0 = 2 * load / (math.pi * aa)
    geo = mirror_geometry(a)
    cx, base, z = geo["cx"], geo["base"], a.zone
    mesh = "graded" if a.graded else "uniform"
    title = a.title or (
        f"Hertz, two equal cylinders ({mesh} mesh): a = {aa}, R = {r}, R* = {rs}"
        if a.cattaneo is None
        else f"Cattaneo-Mindlin, two equal cylinders pressed then shifted ({mesh} mesh): "
        f"mu = {a.cattaneo}, R = {r}, R* = {rs}"
    )
    out = mirror_header(a, geo, e_star, rs, load, p0)
    out += [f"title = {title!r}".replace("'", '"'), ""]
    out += mirror_body("upper", geo["upper"], a, [cx - z, cx + z, base, base + z])
    out += mirror_body("lower", geo["lower"], a, [cx - z, cx + z, base - z, base])
    out += ["[[dirichlet]]", 'body = "lower"', f"region = [0.0, {w!r}, {geo['bottom']!r}, {geo['bottom']!r}]", ""]
    region = f"region = [0.0, {w!r}, {geo['top']!r}, {geo['top']!r}]"
    if a.cattaneo is None:
        out += ["[[dirichlet]]", 'body = "upper"', region, 'components = ["x"]', ""]
        out += ["[[neumann]]", 'body = "upper"', region, f"traction = [0.0, {-load / w!r}]", ""]
    else:
        for name, comp, value in (("press", "y", [0.0, -a.press]), ("shift", "x", [a.shift, 0.0])):
            out += ["[[dirichlet]]", f'name = "{name}"', 'body = "upper"', region,
                    f'components = ["{comp}"]', f"value = [{value[0]!r}, {value[1]!r}]", ""]
    out += ["[[contact]]", 'bodies = ["upper", "lower"]',
            f"region = [{num(cx - 0.2)}, {num(cx + 0.2)}, {num(base - 0.01)}, {num(base + 0.01)}]",
            'slave = "lower"', f'formulation = "{a.formulation}"']
    if a.cattaneo is not None:
        out += [f"friction = {a.cattaneo!r}", "", "[[step]]", "loads = { press = 1.0 }", "",
                "[[step]]", "loads = { press = 1.0, shift = 1.0 }", f"increments = {a.increments}"]
    out += ["", "[reference]", f"centre = [{cx!r}, {base!r}]"]
    if a.cattaneo is None:
        out += [f"half_width = {aa!r}", f"peak_pressure = {p0!r}"]
    else:
        out += [f"radius = {rs!r}", f"contact_modulus = {e_star!r}", f"friction = {a.cattaneo!r}"]
    print("\n".join(out))

if __name__ == "__main__":
    main()
