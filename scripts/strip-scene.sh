#!/bin/sh
# strip-scene.sh: writes a long-interface scene (docs/scene.md format) to standard output: a
# strip pressed along its whole length onto a foundation, so that every contact row is active
# (or, with --loaded, on a part of it only, so that its ends lift off: partial contact).
#
# Usage: scripts/strip-scene.sh [--length L] [--hmax H] [--strip-layers NS]
#            [--foundation-layers NF] [--support floating|clamped] [--load P]
#            [--loaded X0,X1] [--young E] [--poisson NU] [--title TEXT]
# Defaults: L 3, H 0.01, NS 2, NF 4, floating, P 1e-3, the whole top loaded, E 1, NU 0.3.
#   thin strip: NS = 2 (two elements through the thickness); thick strip: NS = 10.
# Dependency-free (POSIX sh and awk). Contact rows m = L/H + 1 (one per slave node on the
# interface); free DOFs grow as about 2 (L/H)(NS + NF) times a mesher factor of about 1.6.
#
# The scene (written into the generated file's header as well):
#   strip      [0,L] x [1, 1+ts], ts = NS*H   (E, NU)
#   foundation [0,L] x [1-tf, 1], tf = NF*H   (E, NU), clamped (ux = uy = 0) on its bottom y = 1-tf
#   uniform traction (0, -P) on the strip's top y = 1+ts (on 0 <= X0 <= x <= X1 <= L only with
#   --loaded X0,X1); frictionless contact on y = 1.
#   support of the strip:
#     floating: ux = 0 on its left end x = 0 only (a roller); nothing holds it in y but contact,
#               so the stiffness matrix A is singular (vertical translation) and the contact
#               rows alone make the problem well posed.
#     clamped:  ux = uy = 0 on its left end x = 0.
#
# Expected physics (plane strain, linear elasticity; M = E(1-NU)/((1+NU)(1-2NU)) the constrained
# modulus):
#   * floating: the strip's only vertical support is contact, so the total contact force equals
#     the applied load P*L exactly (up to the solve tolerance). The strip is in uniform uniaxial
#     stress: sigma_yy = -P, sigma_xx = sigma_xy = 0 (free top, frictionless bottom, free right
#     end, roller at the left end), sigma_zz = NU*sigma_yy (plane strain), hence
#     eps_yy = -P(1-NU^2)/E and eps_xx = P NU (1+NU)/E (it spreads sideways, sliding on the
#     foundation). Away from its free ends (a few thicknesses), the foundation is in uniaxial
#     strain (its bottom is clamped, its top is frictionless): ux = 0, eps_yy = -P/M, so its top
#     settles by P tf/M. Hence, in the middle of the strip:
#       uy(strip top) - uy(strip bottom) = -P ts (1-NU^2)/E,  uy(interface) = -P tf/M,
#     and the contact pressure equals P: the multiplier of a row is P times the slave node's
#     tributary length. These fields are linear, so P1 elements reproduce them exactly; only the
#     end effects (decaying over a beam-on-foundation length 1/beta, beta^4 = k/(4 E'I),
#     k = M/tf, E'I = E ts^3/(12(1-NU^2))) perturb them, by exp(-beta L/3) in the middle third.
#   * clamped: the same in the middle of the strip; near the clamp the strip is held up while
#     the foundation settles, so the clamp carries part of the load (about P/beta for a
#     semi-infinite beam on a Winkler foundation) and a few rows next to it may open.
#   * every backend either solves it (then all agree) or reports a non-solved status. The dual
#     Hessian B A^-1 B^T of a thin strip is very ill-conditioned (issue 9).
#
#   * partial load (--loaded X0,X1, floating): contact still carries the whole load, P (X1-X0)
#     exactly, and (no other vertical force acts on the strip) its resultant acts at
#     (X0+X1)/2. In the middle of the loaded part (if it is long against 1/beta) the fields
#     are those above. Beyond each end of the load the strip, a weightless beam on a Winkler
#     foundation that cannot pull (E'I w'''' + k w = 0 where it presses), presses on over a
#     length c and lifts off where w = w'' = w''' = 0 (no moment, no shear in the free part):
#     beta c = pi/4 (root of the matching conditions at the load's end, where w = P/(2k)). The
#     free part is straight: it rises with slope sqrt(2) exp(-pi/4) beta P/k, so the strip's
#     right end is lifted by that slope times (L - X1 - c) off the foundation (its gap). The
#     P1 strip is stiffer in bending than E'I (one or two triangles through the thickness
#     lock) and the foundation is a layer, not springs: the model gives the scales, not the
#     digits. The lift is a lever's: the solve tolerance bounds it far less tightly than the
#     rest (the tip's compliance is huge).
#
# Probes: strip-mid-top (Xm, 1+ts), strip-mid-bottom (Xm, 1) on the strip,
#         foundation-mid-top (Xm, 1) on the foundation, Xm = L/2 (the load's middle with --loaded).
# Check a scene: scripts/strip-scene.sh --length 20 > s.toml && signorini check s.toml
set -eu

length=3
hmax=0.01
ns=2
nf=4
support=floating
load=1e-3
loaded=
young=1
poisson=0.3
title=

die() {
  echo "strip-scene.sh: $*" >&2
  exit 1
}

while [ $# -gt 0 ]; do
  [ $# -ge 2 ] || die "$1 needs a value (see the header of this script)"
  case $1 in
    --length) length=$2 ;;
    --hmax) hmax=$2 ;;
    --strip-layers) ns=$2 ;;
    --foundation-layers) nf=$2 ;;
    --support) support=$2 ;;
    --load) load=$2 ;;
    --loaded) loaded=$2 ;;
    --young) young=$2 ;;
    --poisson) poisson=$2 ;;
    --title) title=$2 ;;
    *) die "unknown option $1 (see the header of this script)" ;;
  esac
  shift 2
done

case $support in
  floating | clamped) ;;
  *) die "--support must be floating or clamped, got $support" ;;
esac

awk -v L="$length" -v h="$hmax" -v ns="$ns" -v nf="$nf" -v support="$support" \
  -v p="$load" -v loaded="$loaded" -v E="$young" -v nu="$poisson" -v title="$title" '
function num(s) { return s ~ /^[+]?([0-9]+[.]?[0-9]*|[.][0-9]+)([eE][-+]?[0-9]+)?$/ }
function fmt(x) { return sprintf("%.12g", x) }
BEGIN {
  if (!num(L) || L + 0 <= 0) { print "strip-scene.sh: --length must be a positive number" > "/dev/stderr"; exit 1 }
  if (!num(h) || h + 0 <= 0) { print "strip-scene.sh: --hmax must be a positive number" > "/dev/stderr"; exit 1 }
  if (ns !~ /^[1-9][0-9]*$/ || nf !~ /^[1-9][0-9]*$/) { print "strip-scene.sh: layers must be positive integers" > "/dev/stderr"; exit 1 }
  if (!num(p) || !num(E) || E + 0 <= 0) { print "strip-scene.sh: --load and --young must be non-negative numbers, E > 0" > "/dev/stderr"; exit 1 }
  if (!num(nu) || nu + 0 >= 0.5) { print "strip-scene.sh: --poisson must lie in [0, 0.5)" > "/dev/stderr"; exit 1 }
  L += 0; h += 0; p += 0; E += 0; nu += 0
  x0 = 0; x1 = L; partial = 0
  if (loaded != "") {
    if (split(loaded, span, ",") != 2 || !num(span[1]) || !num(span[2]) || span[1] + 0 >= span[2] + 0 || span[2] + 0 > L) { print "strip-scene.sh: --loaded must be X0,X1 with 0 <= X0 < X1 <= L" > "/dev/stderr"; exit 1 }
    x0 = span[1] + 0; x1 = span[2] + 0
    partial = (x0 > 0 || x1 < L)
  }
  xm = (x0 + x1) / 2
  ts = ns * h; tf = nf * h
  top = 1 + ts; bottom = 1 - tf
  M = E * (1 - nu) / ((1 + nu) * (1 - 2 * nu))
  rows = int(L / h + 0.5) + 1
  if (title == "") title = sprintf("Long interface: %s strip (%d layers) on a foundation (%d layers), %s, L = %s, hmax = %s", (ns <= 2 ? "thin" : "thick"), ns, nf, support, fmt(L), fmt(h))
  if (partial && title == sprintf("Long interface: %s strip (%d layers) on a foundation (%d layers), %s, L = %s, hmax = %s", (ns <= 2 ? "thin" : "thick"), ns, nf, support, fmt(L), fmt(h)))
    title = title sprintf(", loaded on [%s, %s] only (partial contact)", fmt(x0), fmt(x1))
  gsub(/"/, "", title)
  printf "# LONG INTERFACE (generated by scripts/strip-scene.sh --length %s --hmax %s --strip-layers %d\n", fmt(L), fmt(h), ns
  printf "#   --foundation-layers %d --support %s --load %s%s --young %s --poisson %s).\n", nf, support, fmt(p), (partial ? " --loaded " fmt(x0) "," fmt(x1) : ""), fmt(E), fmt(nu)
  printf "# strip [0,%s]x[1,%s] (%d elements thick) pressed by a uniform traction %s in -y on its top%s\n", fmt(L), fmt(top), ns, fmt(p), (partial ? " on [" fmt(x0) ", " fmt(x1) "] only" : "")
  printf "# onto a foundation [0,%s]x[%s,1] (%d elements thick) clamped on its bottom; frictionless\n", fmt(L), fmt(bottom), nf
  if (partial)
    printf "# contact on y = 1, conforming (same hmax), about %d rows; those under the load press, the rest open.\n", rows
  else
    printf "# contact on y = 1, conforming (same hmax), about %d rows, all pressed.\n", rows
  if (support == "floating")
    print "# The strip is held in x only, at its left end (roller): contact alone holds it vertically (A singular)."
  else
    print "# The strip is clamped (ux = uy = 0) at its left end."
  print "# Expected (plane strain; M = E(1-nu)/((1+nu)(1-2nu)) the constrained modulus):"
  if (partial && support == "floating")
    printf "# * total contact force = applied load p (x1 - x0) = %s exactly, its resultant at x = %s (moments);\n", fmt(p * (x1 - x0)), fmt(xm)
  else if (partial)
    printf "# * total contact force = p (x1 - x0) = %s minus the share of the clamp;\n", fmt(p * (x1 - x0))
  else if (support == "floating")
    printf "# * total contact force = applied load p L = %s exactly (contact is the only vertical support);\n", fmt(p * L)
  else
    printf "# * total contact force = p L = %s minus the share of the clamp (about p/beta, see below);\n", fmt(p * L)
  if (partial)
    printf "# * middle third of the loaded part: contact pressure = p = %s (multiplier = p x tributary length);\n", fmt(p)
  else
    printf "# * middle third: contact pressure = p = %s (multiplier = p x tributary length), every row active;\n", fmt(p)
  printf "#   strip in uniaxial stress: uy(top) - uy(bottom) = -p ts (1-nu^2)/E = %s;\n", fmt(-p * ts * (1 - nu * nu) / E)
  printf "#   foundation in uniaxial strain: uy(interface) = -p tf/M = %s%s\n", fmt(-p * tf / M), (support == "floating" ? ";" : ".")
  if (support == "floating" && !partial)
    printf "#   the strip spreads sideways: ux = p nu (1+nu) x/E (it slides on the foundation).\n"
  Ep = E / (1 - nu * nu); I = ts * ts * ts / 12; k = M / tf
  beta = exp(log(k / (4 * Ep * I)) / 4)
  printf "# * end effects decay over 1/beta = %s (beam on a Winkler foundation, beta^4 = (M/tf)/(4 E'"'"'I),\n", fmt(1 / beta)
  print "#   E'"'"' = E/(1-nu^2), I = ts^3/12): linear fields, exact for P1 elements, hold in the middle third."
  if (partial) {
    pi = atan2(0, -1); c = pi / (4 * beta); slope = sqrt(2) * exp(-pi / 4) * beta * p / k
    printf "# * lift-off (a weightless beam on a tensionless Winkler foundation): contact reaches c = pi/(4 beta)\n"
    printf "#   = %s beyond each end of the load, then the strip rises with slope sqrt(2) exp(-pi/4) beta p/k\n", fmt(c)
    printf "#   = %s: its right end by %s (P1 strips are stiffer in bending: scales, not digits).\n", fmt(slope), fmt(slope * (L - x1 - c))
    print "#   The end lift is a lever: the solve tolerance bounds it loosely (the expectation allows for it)."
  }
  print "# * every backend solves it to the tolerance (and they agree) or reports a non-solved status."
  printf "title = \"%s\"\n\n", title
  printf "[[body]]\nname = \"strip\"\npolygon = [[0, 1], [%s, 1], [%s, %s], [0, %s]]\n", fmt(L), fmt(L), fmt(top), fmt(top)
  printf "hmax = %s\nyoung = %s\npoisson = %s\n\n", fmt(h), fmt(E), fmt(nu)
  printf "[[body]]\nname = \"foundation\"\npolygon = [[0, %s], [%s, %s], [%s, 1], [0, 1]]\n", fmt(bottom), fmt(L), fmt(bottom), fmt(L)
  printf "hmax = %s\nyoung = %s\npoisson = %s\n\n", fmt(h), fmt(E), fmt(nu)
  printf "[[dirichlet]]\nbody = \"foundation\"\nregion = [0, %s, %s, %s]\n\n", fmt(L), fmt(bottom), fmt(bottom)
  printf "[[dirichlet]]\nbody = \"strip\"\nregion = [0, 0, 1, %s]\n", fmt(top)
  if (support == "floating") printf "components = [\"x\"]\n"
  printf "\n[[neumann]]\nbody = \"strip\"\nregion = [%s, %s, %s, %s]\ntraction = [0, %s]\n\n", fmt(x0), fmt(x1), fmt(top), fmt(top), fmt(-p)
  # The box reaches h/4 either side of y = 1: the interface nodes only, not the next ones up
  # the end edges (at y = 1 +- h).
  printf "[[contact]]\nbodies = [\"strip\", \"foundation\"]\nregion = [0, %s, %s, %s]\n\n", fmt(L), fmt(1 - h / 4), fmt(1 + h / 4)
  printf "[[probe]]\nname = \"strip-mid-top\"\nbody = \"strip\"\npoint = [%s, %s]\n\n", fmt(xm), fmt(top)
  printf "[[probe]]\nname = \"strip-mid-bottom\"\nbody = \"strip\"\npoint = [%s, 1]\n\n", fmt(xm)
  printf "[[probe]]\nname = \"foundation-mid-top\"\nbody = \"foundation\"\npoint = [%s, 1]\n", fmt(xm)
}'
