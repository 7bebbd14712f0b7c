#!/bin/sh
# A grab scene in other units, law and mesh than the bundled ones (docs/benchmarks.md, "Grab probe:
# where it stands"): data/meshes/liverCoarse.vtu (centimetres) scaled to millimetres, a
# Mooney-Rivlin liver, a node under the left lobe grabbed, a 7 x 7 x 7 workspace at 5 mm.
# Writes DIR/liverCoarse_mm.vtu and DIR/scene.toml (add `radius = 8.0` under [probe] for a patch).
# Usage: sh bench/scenes/liver-coarse-mm.sh DIR && build/tools/hapstate run DIR/scene.toml --state DIR/state --nodes all
set -eu
dir=${1:?usage: liver-coarse-mm.sh DIR}
here=$(cd "$(dirname "$0")" && pwd)
mkdir -p "$dir"
python3 - "$here/../../data/meshes/liverCoarse.vtu" "$dir/liverCoarse_mm.vtu" <<'PY'
import sys
text = open(sys.argv[1]).read()
start = text.index('>', text.index('<DataArray', text.index('<Points>'))) + 1
end = text.index('</DataArray>', start)
points = ' '.join('%.6g' % (10.0 * float(v)) for v in text[start:end].split())
open(sys.argv[2], 'w').write(text[:start] + '\n' + points + '\n' + text[end:])
PY
cat > "$dir/scene.toml" <<'TOML'
[mesh]
file = "liverCoarse_mm.vtu"                # liverCoarse.vtu x 10: millimetres
unit = 0.001

[material]
law = "mooney"
c10 = 600.0                                # Pa
c01 = 262.0                                # Pa
d1 = 1.2e-4                                # 1/Pa

[[fixed]]
box = [[0.0, 30.0, -10.0], [20.0, 50.0, 20.0]]  # the SOFA liver fixture, in millimetres

[probe]
mode = "grab"
point = [-29.1171, 29.7596, -16.6064]      # the lowest node of the left lobe
max_force = 3.0

[grid]
spacing = 5.0
box = [[-44.1171, 14.7596, -31.6064], [-14.1171, 44.7596, -1.6064]]

[solver]
substeps = 4
tolerance = 1e-8
max_iterations = 30
TOML
echo "wrote $dir/liverCoarse_mm.vtu and $dir/scene.toml"
