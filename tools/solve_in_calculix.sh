#!/usr/bin/env bash
# Solves om_dthex's .inp of the femur and the vertebra in CalculiX and writes the solver's time and
# memory into docs/BENCHMARKS.md (between its calculix-table markers; a rerun replaces them).
# The deck is the one tests/regression/calculix_test.cpp solves on a small box, built from the
# names in the .inp alone: its own *HEADING, *INCLUDE of the mesh, a linear elastic bone
# (E = 17 GPa, nu = 0.3), the flattest boundary patch of 1% of the area or more fixed (the femur's
# distal cut), a pressure of 1 MPa on every other patch, one static step. The boundary is closed,
# so the pressure on the rest pushes with the pressure times the fixed patch's area; ccx's reaction
# must balance it less the share the loaded faces put on the fixed patch's own nodes (ccx leaves
# loads on fixed nodes out of RF). The table gives the relative error, and that ccx printed no
# error or warning. ccx runs under /usr/bin/time -v (the femur: about 100 s and 2.4 GB), so run it
# on a machine with little else to do.
#
#   bash tools/solve_in_calculix.sh                    the femur (mm) and the vertebra (m)
#   bash tools/solve_in_calculix.sh MESH.off:UNIT ...  other inputs; UNIT is mm or m
#   bash tools/solve_in_calculix.sh --threads 1        OMP_NUM_THREADS for ccx (default 2)
#   bash tools/solve_in_calculix.sh --build DIR        use DIR/om_dthex (default: build/)
#   bash tools/solve_in_calculix.sh --output FILE      write FILE instead of docs/BENCHMARKS.md
set -euo pipefail
cd "$(dirname "$0")/.."

build=build threads=2 output=docs/BENCHMARKS.md inputs=()
while [ $# -gt 0 ]; do
  case "$1" in
    --build) build=$2; shift 2 ;;
    --threads) threads=$2; shift 2 ;;
    --output) output=$2; shift 2 ;;
    -h|--help) sed -n '2,19p' "$0" | sed 's/^# \{0,1\}//'; exit 0 ;;
    -*) echo "solve_in_calculix.sh: unknown argument '$1' (see --help)" >&2; exit 2 ;;
    *) inputs+=("$1"); shift ;;
  esac
done
[ ${#inputs[@]} -gt 0 ] || inputs=(meshes/femur_proximal_ct.off:mm meshes/vertebra_L1.off:m)
command -v ccx >/dev/null || { echo "solve_in_calculix.sh: no ccx (tools/setup.sh installs calculix-ccx)" >&2; exit 2; }
[ -x "$build/om_dthex" ] || { echo "solve_in_calculix.sh: $build/om_dthex not built" >&2; exit 2; }

work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT

# From the .inp: node and hex counts, the longest *NODE field (CalculiX reads 20 characters),
# and for each patch its outward vector area (C3D8 faces S1..S6) and flatness (its nodes' spread
# along that vector over the square root of its area). Prints the flattest patch of 1% of the
# area or more, its vector area, the unit pressure's load on its nodes, its flatness, the others.
cat >"$work/patches.py" <<'PYTHON'
import math, re, sys
faces = {1: (0, 1, 2, 3), 2: (4, 7, 6, 5), 3: (0, 4, 5, 1), 4: (1, 5, 6, 2), 5: (2, 6, 7, 3), 6: (3, 7, 4, 0)}
nodes, hexes, surfaces, section, widest = {}, {}, {}, None, 0
for line in open(sys.argv[1]):
    line = line.strip()
    if line.startswith("**") or not line:
        continue
    if line.startswith("*"):
        m = re.match(r"\*SURFACE, NAME=(patch\d+), TYPE=ELEMENT", line)
        section = "node" if line == "*NODE" else "hex" if line.startswith("*ELEMENT") else m.group(1) if m else None
        if m: surfaces[section] = []
        continue
    fields = line.split(",")
    if section == "node":
        nodes[int(fields[0])] = [float(f) for f in fields[1:]]
        widest = max(widest, *map(len, fields[1:]))
    elif section == "hex":
        hexes[int(fields[0])] = [int(f) for f in fields[1:]]
    elif section:
        surfaces[section].append((int(fields[0]), int(fields[1].strip()[1:])))
def corners(element, side): return [hexes[element][i] for i in faces[side]]
def add(a, b, w=1.0): return [a[i] + w * b[i] for i in range(3)]
def cross(a, b): return [a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]]
def norm(a): return math.sqrt(sum(c * c for c in a))
total_area = sum(norm(cross(add(nodes[q[3]], nodes[q[1]], -1), add(nodes[q[2]], nodes[q[0]], -1))) / 2
                 for sides in surfaces.values() for q in (corners(*s) for s in sides))
rows = []
for name, sides in surfaces.items():
    vector, area, points = [0.0] * 3, 0.0, set()
    for side in sides:
        q = [nodes[n] for n in corners(*side)]
        a = cross(add(q[3], q[1], -1), add(q[2], q[0], -1))  # twice a bilinear quad's outward vector area
        vector, area = add(vector, a, 0.5), area + norm(a) / 2
        points.update(corners(*side))
    heights = [sum(nodes[p][i] * vector[i] for i in range(3)) / norm(vector) for p in points]
    if area >= 0.01 * total_area:
        rows.append(((max(heights) - min(heights)) / math.sqrt(area), name, vector, points))
rows.sort()
flatness, fixed, vector, fixed_nodes = rows[0]
# A unit pressure's consistent nodal forces (2x2 Gauss points, exact on bilinear faces) on the
# fixed patch's nodes from the faces of the other patches around it.
g, rim = 1 / math.sqrt(3), [0.0] * 3
for side in (s for name, sides in surfaces.items() if name != fixed for s in sides):
    ids = corners(*side)
    if not fixed_nodes.intersection(ids): continue
    q = [nodes[n] for n in ids]
    for u, v in ((-g, -g), (g, -g), (g, g), (-g, g)):
        shape = [(1 - u) * (1 - v) / 4, (1 + u) * (1 - v) / 4, (1 + u) * (1 + v) / 4, (1 - u) * (1 + v) / 4]
        along_u = add([c * (1 - v) / 4 for c in add(q[1], q[0], -1)], [c * (1 + v) / 4 for c in add(q[2], q[3], -1)])
        along_v = add([c * (1 - u) / 4 for c in add(q[3], q[0], -1)], [c * (1 + u) / 4 for c in add(q[2], q[1], -1)])
        inward = cross(along_u, along_v)  # the faces are listed with the inside on their right
        for a in range(4):
            if ids[a] in fixed_nodes: rim = add(rim, inward, shape[a])
print(len(nodes), len(hexes), widest, fixed, "%.17g %.17g %.17g" % tuple(vector), "%.17g %.17g %.17g" % tuple(rim),
      "%.3g" % flatness, " ".join(name for name in surfaces if name != fixed))
PYTHON

rows=() status=0
for input in "${inputs[@]}"; do
  mesh=${input%:*} unit=${input##*:} name=$(basename "${input%:*}" .off)
  case "$unit" in
    mm) modulus=17000. pressure=1. shown="1 MPa" ;;  # forces in N either way
    m) modulus=17e9 pressure=1e6 shown="1e6 Pa" ;;
    *) echo "solve_in_calculix.sh: unit '$unit' of $mesh is not mm or m" >&2; exit 2 ;;
  esac
  echo "solve_in_calculix.sh: $mesh ($unit)" >&2
  "$build/om_dthex" -q "$mesh" -o "$work/$name.inp"
  read -r nodes hexes widest fixed ax ay az rx ry rz flatness loaded < <(/usr/bin/python3 "$work/patches.py" "$work/$name.inp")
  {
    echo "*HEADING"
    echo "$name: $fixed fixed, pressure on the other patches"
    echo "*INCLUDE, INPUT=$name.inp"
    echo "*MATERIAL, NAME=BONE"
    echo "*ELASTIC"
    echo "$modulus, 0.3"
    echo "*SOLID SECTION, ELSET=SOLID, MATERIAL=BONE"
    echo "*STEP"
    echo "*STATIC"
    echo "*BOUNDARY"
    echo "$fixed, 1, 3, 0."
    echo "*DLOAD"
    for patch in $loaded; do echo "$patch, P, $pressure"; done
    echo "*NODE PRINT, NSET=$fixed, TOTALS=ONLY"
    echo "RF"
    echo "*END STEP"
  } >"$work/deck_$name.inp"
  (cd "$work" && OMP_NUM_THREADS=$threads /usr/bin/time -v -o "time_$name" ccx -i "deck_$name" >"ccx_$name.log" 2>&1) ||
    { echo "solve_in_calculix.sh: ccx failed on $name:" >&2; tail -n 5 "$work/ccx_$name.log" >&2; status=1; }
  seconds=$(awk -F': ' '/Elapsed \(wall clock\)/ { n = split($2, t, ":"); s = 0
    for (i = 1; i <= n; ++i) s = 60 * s + t[i]; printf "%.0f", s }' "$work/time_$name")
  megabytes=$(awk '/Maximum resident set size/ { printf "%.0f", $NF / 1024 }' "$work/time_$name")
  complaints=$(grep -ciE 'error|warning' "$work/ccx_$name.log" || true)
  # deck.dat: "total force (fx,fy,fz) for set PATCHn ..." and then (after a blank line) fx fy fz.
  read -r fx fy fz < <(awk '/total force/ { found = 1; next } found && NF == 3 { print; exit }' "$work/deck_$name.dat" 2>/dev/null) ||
    { fx=nan fy=nan fz=nan status=1; }
  # The pressure on the rest of the closed boundary pushes with p times the fixed patch's outward
  # vector area A; ccx's reaction balances it less the load p R on the fixed nodes: p (R - A).
  read -r force share error < <(awk -v p="$pressure" -v fx="$fx" -v fy="$fy" -v fz="$fz" -v ax="$ax" -v ay="$ay" \
    -v az="$az" -v rx="$rx" -v ry="$ry" -v rz="$rz" 'BEGIN {
    d = sqrt((fx - p * (rx - ax)) ^ 2 + (fy - p * (ry - ay)) ^ 2 + (fz - p * (rz - az)) ^ 2)
    a = p * sqrt(ax * ax + ay * ay + az * az)
    printf "%.6g %.6g %.1e\n", a, p * sqrt(rx * rx + ry * ry + rz * rz), d / a }')
  [ "$complaints" = 0 ] || status=1
  rows+=("| $name ($unit) | $nodes | $hexes | $widest | $fixed ($flatness) | $shown | $force | $share | $(awk -v x="$fx" -v y="$fy" \
    -v z="$fz" 'BEGIN { printf "%.6g", sqrt(x*x + y*y + z*z) }') | $error | $threads | $seconds | $megabytes | $complaints |")
done

commit=$(git rev-parse --short HEAD)
# (The output file itself does not count: it holds the previous run's table.)
[ -z "$(git status --porcelain --untracked-files=no -- . ":(exclude)$output")" ] || commit="$commit, with uncommitted changes"
{
  echo "<!-- calculix-table:begin -->"
  echo "## Solved in CalculiX"
  echo
  echo "Written by \`bash tools/solve_in_calculix.sh\` $(date -u '+%Y-%m-%d %H:%M UTC'), commit \`$commit\`,"
  echo "on $(sed -n 's/^model name[[:space:]]*: //p' /proc/cpuinfo | head -n 1) ($(nproc) cores), load average $(cut -d' ' -f1-3 /proc/loadavg) at the end, with"
  echo "$(ccx -v 2>&1 | grep -m1 Version | sed 's/.*Version /CalculiX /') (OMP_NUM_THREADS as in the table: 1 when the machine is busy)."
  echo "Each mesh is \`om_dthex MESH.off -o MESH.inp\` at the defaults, included in a deck with its own"
  echo "\`*HEADING\`: the flattest patch of 1% of the boundary area or more fixed (flatness: its nodes'"
  echo "spread off its plane over the square root of its area; the femur's is its distal cut), a"
  echo "pressure on every other patch, E = 17 GPa and nu = 0.3 in the mesh's units, one static step."
  echo "Forces are in newtons. The rest of the closed boundary pushes with pressure x the fixed patch's area;"
  echo "ccx's reaction balances that less the pressure's share on the fixed patch's own nodes (its rim),"
  echo "which ccx leaves out of RF. The error is of the reaction vector against that, relative to"
  echo "pressure x area. Field is the widest \`*NODE\` coordinate in characters: CalculiX reads 20,"
  echo "so every coordinate is read whole (the vertebra is in metres)."
  echo "Seconds and peak MB are ccx's alone (\`/usr/bin/time -v\`)."
  echo
  echo "| mesh (unit) | nodes | hexes | field | fixed (flatness) | pressure | pressure x area | share on the rim | reaction | error | ccx threads | ccx seconds | ccx peak MB | ccx errors and warnings |"
  echo "|---|---:|---:|---:|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|"
  printf '%s\n' "${rows[@]}"
  echo "<!-- calculix-table:end -->"
} >"$work/section.md"

touch "$output"
if grep -q '<!-- calculix-table:begin -->' "$output"; then
  awk -v table="$work/section.md" '
    /<!-- calculix-table:begin -->/ { while ((getline line < table) > 0) print line; skipping = 1; next }
    /<!-- calculix-table:end -->/ { skipping = 0; next }
    !skipping { print }' "$output" >"$work/output.md"
else
  { cat "$output"; echo; cat "$work/section.md"; } >"$work/output.md"
fi
cat "$work/output.md" >"$output"
cat "$work/section.md"
exit "$status"
