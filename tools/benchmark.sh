#!/usr/bin/env bash
# Measures DTHex against THex on the bundled meshes and writes docs/BENCHMARKS.md: a header
# with the commit, the date (UTC) and the machine, then the benchmark harness's tables
# (build/benchmark, tools/benchmark_main.cpp). It also rewrites the headline table in
# README.md (between its "headline-table" markers) from the same run, so the README's
# figures and docs/BENCHMARKS.md always come from one measurement.
#
#   bash tools/benchmark.sh                    bundled meshes, plus the femur subdivided 1 to 4 times
#                                              (4: 18.6 million triangles, about 8 GB; refused up
#                                              front, with the memory it needs, where that is short)
#   bash tools/benchmark.sh --scaling "1 2"    scaling rows for 1 and 2 Loop subdivisions
#   bash tools/benchmark.sh --scaling ""       no scaling rows
#   bash tools/benchmark.sh --scaling-only     only the scaling rows: they replace that section of
#                                              the output file, the rest stays as measured before
#   bash tools/benchmark.sh --build DIR        use DIR/benchmark (default: build/)
#   bash tools/benchmark.sh --no-readme        leave README.md as it is
#   bash tools/benchmark.sh --output FILE      write FILE instead of docs/BENCHMARKS.md
#   bash tools/benchmark.sh --only NAME        only bundled meshes whose file name contains NAME
#                                              (a partial table: use with --output, --no-readme)
#   bash tools/benchmark.sh --source-commit REV  the commit the binary was built from, when the
#                                              build folder's sources have moved on since
#   bash tools/benchmark.sh --peers DIR        inputs NAME.off with published meshes NAME_*.vtu
#                                              beside them (default ../shared/meshes/peer; "" or a
#                                              missing folder: the comparison is left out)
#   bash tools/benchmark.sh --peers-only       only the comparison with published meshes: it
#                                              replaces that section of the output file, the rest
#                                              stays as measured before
#
# Each run is a child process of the harness with a timeout (--timeout, default 400 s; the
# scaling rows --scaling-timeout, default 1800 s).
# Wall-clock seconds depend on the machine and on what else runs on it: run it on an idle one.
set -euo pipefail
cd "$(dirname "$0")/.."
repo=$(pwd)

build=build
scaling="1 2 3 4"
scaling_timeout=1800
scaling_mesh=meshes/femur_proximal_ct.off
timeout=400
update_readme=1
output=docs/BENCHMARKS.md
only=""
source_commit=""
peers=../shared/meshes/peer
peers_only=0
scaling_only=0
while [ $# -gt 0 ]; do
  case "$1" in
    --build) build=$2; shift 2 ;;
    --scaling) scaling=$2; shift 2 ;;
    --scaling-mesh) scaling_mesh=$2; shift 2 ;;
    --timeout) timeout=$2; shift 2 ;;
    --scaling-timeout) scaling_timeout=$2; shift 2 ;;
    --no-readme) update_readme=0; shift ;;
    --only) only=$2; shift 2 ;;
    --source-commit) source_commit=$2; shift 2 ;;
    --output) output=$2; shift 2 ;;
    --peers) peers=$2; shift 2 ;;
    --peers-only) peers_only=1; update_readme=0; shift ;;
    --scaling-only) scaling_only=1; update_readme=0; shift ;;
    -h|--help) sed -n '2,31p' "$0" | sed 's/^# \{0,1\}//'; exit 0 ;;
    *) echo "benchmark.sh: unknown argument '$1' (see --help)" >&2; exit 2 ;;
  esac
done

bench="$build/benchmark"
shown="$(basename "$build")/benchmark"  # as the files name it: no path outside the repository
if [ ! -f "$build/CMakeCache.txt" ]; then
  echo "benchmark.sh: $build is not a build folder; build first (bash tools/setup.sh)" >&2
  exit 2
fi
# Brought up to date with its sources first, so the figures are the checked-out commit's.
built_now=0
if cmake --build "$build" -j"$(nproc)" --target benchmark om_dthex hex_quality >"$build/benchmark-build.log" 2>&1; then
  built_now=1
else
  echo "benchmark.sh: building in $build failed (see $build/benchmark-build.log); measuring the binaries there" >&2
fi
if [ ! -x "$bench" ]; then
  echo "benchmark.sh: $bench not found; build first (bash tools/setup.sh)" >&2
  exit 2
fi

# The sources the binary was built from: the build's CMake source folder, if it is a git tree.
source_dir=$(sed -n 's/^CMAKE_HOME_DIRECTORY:INTERNAL=//p' "$build/CMakeCache.txt" 2>/dev/null || true)
[ -n "$source_dir" ] || source_dir=$repo
if [ -n "$source_commit" ]; then
  commit=$(git -C "$source_dir" rev-parse --short "$source_commit^{commit}" 2>/dev/null || echo "$source_commit")
  tree="as given with --source-commit; HEAD of the sources is now $(git -C "$source_dir" rev-parse --short HEAD 2>/dev/null || echo unknown)"
elif git -C "$source_dir" rev-parse --git-dir >/dev/null 2>&1; then
  commit=$(git -C "$source_dir" rev-parse --short HEAD)
  if [ -n "$(git -C "$source_dir" status --porcelain --untracked-files=no)" ]; then
    tree="with uncommitted changes"
  else
    tree="clean"
  fi
  # A binary older than the commit was built from an earlier one (or the build is stale).
  # (With --peers-only the binary that runs is om_dthex.)
  checked=$bench
  if [ "$peers_only" = 1 ]; then checked=$build/om_dthex; shown="$(basename "$build")/om_dthex"; fi
  if [ "$built_now" = 0 ] && [ "$(stat -c %Y "$checked")" -lt "$(git -C "$source_dir" log -1 --format=%ct)" ]; then
    tree="$tree; but $shown is older than this commit, so it may be an earlier one's"
  fi
else
  commit="unknown (not a git tree)"
  tree="unknown"
fi
build_type=$(sed -n 's/^CMAKE_BUILD_TYPE:STRING=//p' "$build/CMakeCache.txt" 2>/dev/null || true)
compiler=$(sed -n 's/^CMAKE_CXX_COMPILER:FILEPATH=//p' "$build/CMakeCache.txt" 2>/dev/null || true)
compiler_version=$("${compiler:-c++}" --version 2>/dev/null | head -n 1 || echo unknown)

cpu=$(sed -n 's/^model name[[:space:]]*: //p' /proc/cpuinfo | head -n 1)
cores=$(nproc 2>/dev/null || echo "?")
memory_gib=$(awk '/^MemTotal:/ { printf "%.1f", $2 / 1048576 }' /proc/meminfo)
os=$(. /etc/os-release 2>/dev/null && echo "${PRETTY_NAME:-unknown}")
kernel=$(uname -r)
load=$(cut -d' ' -f1-3 /proc/loadavg)
started=$(date -u '+%Y-%m-%d %H:%M UTC')

work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
: >"$work/cpu"

# CPU time of the whole machine (/proc/stat) and of our runs (bash's time), so the header can
# say how much of the machine other work took while the tables were measured.
machine_busy() { awk '/^cpu / { print $2 + $3 + $4 + $7 + $8; exit }' /proc/stat; }
hz=$(getconf CLK_TCK 2>/dev/null || echo 100)
TIMEFORMAT='%3U %3S'
busy_before=$(machine_busy)
wall_before=$(date +%s.%N)

status=0

# The comparison with published meshes (--peers): for each DIR/NAME.off with published meshes
# DIR/NAME_SOURCE.vtu beside it, om_dthex at the published node count (--target-nodes, dicing
# chosen), then both meshes measured by one program of ours, build/hex_quality (the quality,
# conformity and distance code om_dthex reports with). The published .vtu files are
# zlib-compressed binary (meshio writes them), so meshio turns them into legacy ASCII VTK first.
# Writes $work/peers.md, the section between the peer-table markers.
peer_section() {
  local dir=$1
  {
    echo "<!-- peer-table:begin -->"
    echo "## Against published meshes"
    echo
    if [ -z "$dir" ] || [ ! -d "$dir" ]; then
      echo "Left out: no folder of published meshes (\`--peers ${dir:-\"\"}\`)."
    elif ! /usr/bin/python3 -c 'import meshio' 2>/dev/null; then
      echo "Left out: /usr/bin/python3 has no meshio (Debian python3-meshio) to read the published meshes."
    elif [ ! -x "$build/om_dthex" ] || [ ! -x "$build/hex_quality" ]; then
      echo "Left out: $build/om_dthex or $build/hex_quality is not built."
    else
      peer_rows "$dir"
    fi
    echo "<!-- peer-table:end -->"
  } >"$work/peers.md"
}

# The measured columns of one row, from hex_quality's JSON: nodes, hexes, avg shape, min SJ,
# inverted, conforming, Hausdorff %, volume %.
measured_cells() {
  local nodes hexes shape sj inverted conforming hausdorff volume
  read -r nodes hexes shape sj inverted conforming hausdorff volume < <(jq -r '[.nodes, .hexes, .shape.avg,
    .scaled_jacobian.min, .inverted, (if .conforming then "yes" else "no" end), .hausdorff_pct_diagonal,
    .volume_pct] | @tsv' "$1")
  printf '| %s | %s | %.3f | %.3f | %s | %s | %.2f | %+.2f |' "$nodes" "$hexes" "$shape" "$sj" "$inverted" \
    "$conforming" "$hausdorff" "$volume"
}

# The table of peer_section: three rows per published mesh, it and ours at the defaults and with
# --min-dihedral 18.
peer_rows() {
  local dir=$1
  cat >"$work/to_legacy_vtk.py" <<'PYTHON'
import sys, meshio
mesh = meshio.read(sys.argv[1])
hexes = [block.data for block in mesh.cells if block.type == "hexahedron"]
count = sum(len(block) for block in hexes)
with open(sys.argv[2], "w") as out:
    out.write("# vtk DataFile Version 4.2\nhexahedra\nASCII\nDATASET UNSTRUCTURED_GRID\n")
    out.write("POINTS %d double\n" % len(mesh.points))
    for p in mesh.points:
        out.write("%.17g %.17g %.17g\n" % (p[0], p[1], p[2]))
    out.write("CELLS %d %d\n" % (count, 9 * count))
    for block in hexes:
        for h in block:
            out.write("8 %s\n" % " ".join(str(int(v)) for v in h))
    out.write("CELL_TYPES %d\n" % count)
    out.write("12\n" * count)
PYTHON
  echo "Measured $(date -u '+%Y-%m-%d %H:%M UTC'), commit \`$commit\` ($tree), on $cpu ($cores cores),"
  echo "load average $(cut -d' ' -f1-3 /proc/loadavg) at the start. For each input \`NAME.off\` in \`$dir\` and"
  echo "each published mesh \`NAME_SOURCE.vtu\` beside it: \`om_dthex NAME.off --target-nodes N\` with N the"
  echo "published mesh's node count (the dicing chosen, as without \`--dice\`; again with \`--min-dihedral 18\`), and the meshes measured by"
  echo "\`$(basename "$build")/hex_quality\` (our own quality, conformity and distance code, the figures om_dthex reports;"
  echo "the published .vtu turned into legacy VTK by meshio). Hausdorff is in % of the input's"
  echo "bounding-box diagonal, volume against the input's; seconds are om_dthex's total (published"
  echo "meshes: see their paper)."
  echo
  echo "| surface | mesh | nodes | hexes | avg shape | min SJ | inverted | conforming | Hausdorff % | volume % | seconds |"
  echo "|---|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|"
  local input published name source nodes seconds error
  for input in "$dir"/*.off; do
    name=$(basename "$input" .off)
    for published in "$dir/$name"_*.vtu; do
      [ -e "$published" ] || continue
      source=$(basename "$published" .vtu); source=${source#"$name"_}
      echo "benchmark.sh: $name against $source" >&2
      if ! /usr/bin/python3 "$work/to_legacy_vtk.py" "$published" "$work/published.vtk" 2>"$work/err" ||
        ! "$build/hex_quality" "$work/published.vtk" "$input" >"$work/published.json" 2>>"$work/err"; then
        echo "| $name | $source | not read: $(head -n 1 "$work/err") | | | | | | | | |"
        status=1
        continue
      fi
      nodes=$(jq -r .nodes "$work/published.json")
      echo "| $name | $source (published) $(measured_cells "$work/published.json") |"
      # At the defaults, then with TetGen's dihedral bound: at a node budget the bound lifts the
      # worst hexes on some surfaces for a looser boundary fit (docs/CASE_STUDIES.md).
      local variant
      for variant in "" "--min-dihedral 18"; do
        rm -f "$work/ours.vtk" "$work/ours.json"
        # shellcheck disable=SC2086 # the variant is empty or two words
        { time timeout "$timeout" "$build/om_dthex" "$input" -q --target-nodes "$nodes" $variant -o "$work/ours.vtk" \
            --report "$work/ours.json" 2>"$work/err"; } 2>>"$work/cpu" || true
        if [ ! -s "$work/ours.json" ] || ! "$build/hex_quality" "$work/ours.vtk" "$input" >"$work/measured.json" 2>>"$work/err"; then
          error=$(grep -v '^$' "$work/err" | head -n 1 | sed 's/^om_dthex: //; s/|/\\|/g')
          echo "| $name | om_dthex --target-nodes $nodes $variant | failed: ${error:-timed out after $timeout s} | | | | | | | | |"
          status=1
          continue
        fi
        seconds=$(jq -r .total_seconds "$work/ours.json")
        printf '| %s | om_dthex%s (eps %.3g, dice %s) %s %.1f |\n' "$name" "${variant:+ $variant}" \
          "$(jq -r .options.eps "$work/ours.json")" "$(jq -r .options.dice "$work/ours.json")" \
          "$(measured_cells "$work/measured.json")" "$seconds"
      done
    done
  done
}

# --peers-only: that section alone, put in place of the one in the output file (or after it).
if [ "$peers_only" = 1 ]; then
  echo "benchmark.sh: published meshes only (--peers ${peers:-\"\"})" >&2
  peer_section "$peers"
  mkdir -p "$(dirname "$output")"
  touch "$output"
  if grep -q '<!-- peer-table:begin -->' "$output"; then
    awk -v table="$work/peers.md" '
      /<!-- peer-table:begin -->/ { while ((getline line < table) > 0) print line; skipping = 1; next }
      /<!-- peer-table:end -->/ { skipping = 0; next }
      !skipping { print }' "$output" >"$work/output.md"
  else
    { cat "$output"; echo; cat "$work/peers.md"; } >"$work/output.md"
  fi
  cat "$work/output.md" >"$output"
  echo "benchmark.sh: wrote the published-mesh section of $output" >&2
  cat "$work/peers.md"
  exit "$status"
fi

# The scaling rows: the scaling mesh Loop-subdivided K times for each K of --scaling, DTHex
# only; a summary table (the pipeline against its own floor, reading and verifying the input,
# and the peak memory) and each K's tables. Writes $work/scaling.md, the section between the
# scaling-table markers.
scaling_section() {
  local k
  for k in $scaling; do
    echo "benchmark.sh: $scaling_mesh Loop-subdivided $k times, DTHex only" >&2
    { time "$bench" "$scaling_mesh" --methods dthex --subdivide "$k" --work-dir "$work/subdivided" --timeout "$scaling_timeout" \
        --markdown --csv "$work/scaling_$k.csv" >"$work/scaling_$k.md" 2>&3 || status=$?; } 3>&2 2>>"$work/cpu"
    rm -f "$work/subdivided"/*.off  # up to gigabytes each
  done
  {
    echo "<!-- scaling-table:begin -->"
    echo "## Scaling with input size"
    echo
    if [ -z "$scaling" ]; then
      echo "Left out (\`--scaling \"\"\`)."
    else
      echo "\`$scaling_mesh\` Loop-subdivided K times (4^K times the triangles), DTHex only"
      echo "(\`$shown $scaling_mesh --methods dthex --subdivide K --markdown\`), measured"
      echo "$(date -u '+%Y-%m-%d %H:%M UTC'), commit \`$commit\` ($tree), load average $(cut -d' ' -f1-3 /proc/loadavg) at the"
      echo "start. The bundled table above is K = 0. \"Floor\" is the seconds the run spent reading and"
      echo "verifying its input, \"x floor\" the pipeline's seconds over it; \"then write\" the seconds"
      echo "to write the mesh after that (.vtu with parts and boundary patches, as om_dthex writes it),"
      echo "not in the pipeline's seconds; peak MB is the run's largest resident set, and the stage"
      echo "that reached it."
      echo
      echo "| K | triangles | nodes | seconds | floor (read + verify) | x floor | coarsen | then write | peak MB | at stage |"
      echo "|---:|---:|---:|---:|---:|---:|---:|---:|---:|---|"
      for k in $scaling; do
        awk -F, -v k="$k" '
          NR == 1 { for (i = 1; i <= NF; ++i) col[$i] = i; next }
          $col["status"] != "ok" {
            # The message is the last column, quoted when it holds a comma; no column before it does.
            message = $0
            for (i = 1; i < col["message"]; ++i) sub(/^[^,]*,/, "", message)
            gsub(/^"|"$/, "", message); gsub(/""/, "\"", message); gsub(/\|/, "\\|", message)
            printf "| %s | %s | | %s: %s | | | | | | |\n", k, $col["input_triangles"], $col["status"], message
            next
          }
          {
            floor = $col["t_read"] + $col["t_verify"]; peak = 0; at = ""
            for (c in col) if (c ~ /^peak_mb_/ && $col[c] != "" && $col[c] + 0 > peak) { peak = $col[c] + 0; at = substr(c, 9) }
            gsub(/_/, " ", at)
            printf "| %s | %s | %s | %.2f | %.2f | %.1f | %.2f | %.2f | %.0f | %s |\n", k, $col["input_triangles"], $col["nodes"],
                   $col["total_seconds"], floor, (floor > 0 ? $col["total_seconds"] / floor : 0), $col["t_coarsen"],
                   $col["t_write"], $col["peak_mb"], at
          }' "$work/scaling_$k.csv"
      done
      for k in $scaling; do
        echo
        echo "### K = $k"
        echo
        cat "$work/scaling_$k.md"
      done
    fi
    echo "<!-- scaling-table:end -->"
  } >"$work/scaling.md"
}

# --scaling-only: that section alone, put in place of the one in the output file (or after it).
if [ "$scaling_only" = 1 ]; then
  scaling_section
  mkdir -p "$(dirname "$output")"
  touch "$output"
  if grep -q '<!-- scaling-table:begin -->' "$output"; then
    awk -v table="$work/scaling.md" '
      /<!-- scaling-table:begin -->/ { while ((getline line < table) > 0) print line; skipping = 1; next }
      /<!-- scaling-table:end -->/ { skipping = 0; next }
      !skipping { print }' "$output" >"$work/output.md"
  elif grep -q '^## Scaling with input size$' "$output"; then
    # Written before the section had its markers: it runs to the next section.
    awk -v table="$work/scaling.md" '
      /^## Scaling with input size$/ { while ((getline line < table) > 0) print line; print ""; skipping = 1; next }
      skipping && (/^## / || /^<!-- /) { skipping = 0 }
      !skipping { print }' "$output" >"$work/output.md"
  else
    { cat "$output"; echo; cat "$work/scaling.md"; } >"$work/output.md"
  fi
  cat "$work/output.md" >"$output"
  echo "benchmark.sh: wrote the scaling section of $output" >&2
  cat "$work/scaling.md"
  exit "$status"
fi

echo "benchmark.sh: bundled meshes ($bench, timeout $timeout s per run)" >&2
{ time "$bench" --meshes meshes ${only:+--only "$only"} --timeout "$timeout" --markdown --csv "$work/bundled.csv" \
    >"$work/bundled.md" 2>&3 || status=$?; } 3>&2 2>>"$work/cpu"
scaling_section
peer_section "$peers"
finished=$(date -u '+%H:%M UTC')
busy_after=$(machine_busy)
wall_after=$(date +%s.%N)
# Share of the machine's CPU time (cores x wall time) that processes other than ours used.
others=$(awk -v b0="$busy_before" -v b1="$busy_after" -v hz="$hz" -v w0="$wall_before" -v w1="$wall_after" \
  -v c="$cores" '{ ours += $1 + $2 } END {
    total = (b1 - b0) / hz; avail = (w1 - w0) * c; other = total - ours; if (other < 0) other = 0
    printf "%.0f", (avail > 0 ? 100 * other / avail : 0) }' "$work/cpu")

# One row per mesh from the harness's CSV, THex beside DTHex: the README's headline columns.
# A last line says whether every mesh was valid (no inverted hex) and conforming.
headline() {
  awk -F, '
    function commas(n,   s, out) {
      s = sprintf("%d", n); out = ""
      while (length(s) > 3) { out = "," substr(s, length(s) - 2) out; s = substr(s, 1, length(s) - 3) }
      return s out
    }
    function pair(a, b) { return a " / " b }
    NR == 1 { for (i = 1; i <= NF; ++i) col[$i] = i; next }
    {
      mesh = $col["mesh"]; m = $col["method"]
      if (!(mesh in seen)) { seen[mesh] = 1; order[++count] = mesh }
      ok[mesh, m] = $col["status"] == "ok"
      status[mesh, m] = $col["status"]
      nodes[mesh, m] = commas($col["nodes"]); hexes[mesh, m] = commas($col["hexes"])
      shape[mesh, m] = sprintf("%.3f", $col["shape_avg"]); sj[mesh, m] = sprintf("%.3f", $col["sj_min"])
      hd[mesh, m] = sprintf("%.3f", $col["hausdorff_pct"]); sec[mesh, m] = sprintf("%.2f", $col["total_seconds"])
      if (ok[mesh, m] && ($col["inverted"] != 0 || $col["conforming"] != "yes")) bad = bad " " mesh " (" m ")"
    }
    END {
      print "| mesh | nodes THex / DTHex | hexes THex / DTHex | avg shape | min scaled Jacobian | Hausdorff % | seconds |"
      print "|---|---:|---:|---:|---:|---:|---:|"
      for (i = 1; i <= count; ++i) {
        x = order[i]
        if (!ok[x, "thex"] || !ok[x, "dthex"]) {
          printf "| %s | THex %s, DTHex %s | | | | | |\n", x, status[x, "thex"], status[x, "dthex"]
          continue
        }
        printf "| %s | %s | %s | %s | %s | %s | %s |\n", x, pair(nodes[x, "thex"], nodes[x, "dthex"]),
               pair(hexes[x, "thex"], hexes[x, "dthex"]), pair(shape[x, "thex"], shape[x, "dthex"]),
               pair(sj[x, "thex"], sj[x, "dthex"]), pair(hd[x, "thex"], hd[x, "dthex"]),
               pair(sec[x, "thex"], sec[x, "dthex"])
      }
      print ""
      if (bad == "") print "Every mesh above is valid (no inverted hex) and conforming, in both methods."
      else print "Not valid or not conforming:" bad "."
    }' "$1"
}

headline "$work/bundled.csv" >"$work/headline.md"

machine="$cpu, $cores cores, $memory_gib GiB, $os (Linux $kernel)"
mkdir -p "$(dirname "$output")"
# The CalculiX section (tools/solve_in_calculix.sh) is measured on its own: it is kept as it is.
calculix=$(sed -n '/<!-- calculix-table:begin -->/,/<!-- calculix-table:end -->/p' "$output" 2>/dev/null || true)
{
  echo "# Benchmarks"
  echo
  echo "Written by \`bash tools/benchmark.sh\`; do not edit by hand (run it again instead)."
  echo
  echo "- Commit: \`$commit\` ($tree), built $build_type with $compiler_version"
  echo "- Date: $started to $finished"
  echo "- Machine: $machine; load average $load at the start;"
  if [ "$others" -ge 10 ]; then
    echo "  other processes used $others% of the CPU time while it ran, so the seconds are longer"
    echo "  than on an idle machine (the other columns do not depend on it)"
  else
    echo "  other processes used $others% of the CPU time while it ran"
  fi
  echo "- Harness: \`$shown --meshes meshes --timeout $timeout --markdown\` (each run alone in a child"
  echo "  process; DTHex = \`om_dthex\` at its defaults, THex = \`om_dthex --thex-only\`: TetGen \`pq1.2Y\`"
  echo "  of the input, 4 hexes per tet)"
  echo
  echo "Columns: nodes and hexes of the output; shape is Knupp's hex shape metric and \"min SJ\" the"
  echo "smallest hex scaled Jacobian, both as Verdict (ParaView, VTK) defines them (1 ideal, 0 or"
  echo "less degenerate or inverted); Hausdorff is the two-sided distance between the hex mesh's"
  echo "boundary and the input surface, in % of the input's bounding-box diagonal; volume error is"
  echo "against the input's volume; seconds are the pipeline's wall time, from reading the input to"
  echo "measuring the mesh (writing it follows: \"then write\" in the per-stage table), and peak MB"
  echo "the run's largest resident set. In the per-stage tables \"thin walls\" is the prediction of"
  echo "thin walls, which sets up the coarsening (features, curvature sizes); \"tet edits\" the edits"
  echo "of TetGen's tets before THex; \"smooth\" the local smoother of the worst hexes and its lift;"
  echo "\"regions\" the optimization of the worst regions. Times vary from run to run on a shared"
  echo "machine; the other columns do not."
  echo
  echo "## DTHex against THex, the bundled meshes"
  echo
  echo "The README's headline table:"
  echo
  cat "$work/headline.md"
  echo
  echo "All columns:"
  echo
  cat "$work/bundled.md"
  echo
  echo
  cat "$work/scaling.md"
  echo
  cat "$work/peers.md"
  [ -z "$calculix" ] || printf '\n%s\n' "$calculix"
} >"$output"
echo "benchmark.sh: wrote $output" >&2

if [ "$update_readme" = 1 ] && grep -q '<!-- headline-table:begin -->' README.md; then
  {
    echo "Measured $started on $cpu ($cores cores), commit \`$commit\`$([ "$others" -ge 10 ] &&
      echo ", with other work using $others% of the CPU time (so longer seconds)"); all columns and the" \
      "seconds per stage in [docs/BENCHMARKS.md](docs/BENCHMARKS.md):" | fmt -w 98
    echo
    cat "$work/headline.md"
  } >"$work/readme_table.md"
  awk -v table="$work/readme_table.md" '
    /<!-- headline-table:begin -->/ { print; while ((getline line < table) > 0) print line; skipping = 1; next }
    /<!-- headline-table:end -->/ { skipping = 0 }
    !skipping { print }' README.md >"$work/README.md"
  cat "$work/README.md" >README.md
  echo "benchmark.sh: updated the headline table in README.md" >&2
fi
cat "$work/headline.md"
exit "$status"
