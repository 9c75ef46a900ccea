#!/usr/bin/env bash
# Hostile input through the `jetshell` program: each case must exit with its code (3 for input, 2 for the command
# line) and print one line naming the problem (checked by a fragment), and finish quickly (a FIFO or /dev/zero
# must not hang or eat memory).
# Usage: hostile_cli_test.sh path/to/jetshell
set -u
js="$1"
dir="$(mktemp -d)"
trap 'rm -rf "$dir"' EXIT
failures=0

# expect CODE FRAGMENT -- COMMAND...: runs COMMAND (at most 20 s), checks its exit code and that stderr holds FRAGMENT.
expect() {
  local code="$1" fragment="$2"
  shift 3
  local err rc
  err="$(timeout 20 "$@" 2>&1 >/dev/null)"
  rc=$?
  if [ "$rc" -ne "$code" ] || [[ "$err" != *"$fragment"* ]]; then
    echo "FAIL: $* -> exit $rc (expected $code), stderr: ${err:0:300}"
    echo "      expected to contain: $fragment"
    failures=$((failures + 1))
  fi
}

static='{"type": "static", "loadSteps": 1}'
scene() {  # scene FILE SHAPE ANALYSIS [EXTRA]
  cat >"$dir/$1" <<JSON
{"gravity": [0, 0, 0],
 "actors": [{"type": "shell", "shape": $2, "colliderType": "None", "fixed": [{"select": {"all": true}}]}],
 "analysis": $3 ${4:-}}
JSON
}
rect='{"generator": "rectangle", "width": 1, "height": 1, "nx": 2, "ny": 2}'

scene huge.json '{"generator": "rectangle", "width": 1, "height": 1, "nx": 65535, "ny": 65535}' "$static"
expect 3 "/actors/0/shape: rectangle grid: the resolution gives 4294967296 vertices" -- "$js" run "$dir/huge.json" --check
scene dt.json "$rect" '{"type": "dynamic", "timeStep": 1e-300, "duration": 1}'
expect 3 "/analysis/timeStep = 1e-300: 1e+300 steps over the duration 1 s, too many (at most 10000000)" -- \
  "$js" run "$dir/dt.json" --check
scene threads.json "$rect" "$static" ', "solver": {"threads": 1000000}'
expect 3 "/solver/threads = 1000000: too large (at most 256)" -- "$js" run "$dir/threads.json" --check
expect 3 "/dev/zero: not a regular file" -- "$js" run /dev/zero --check
expect 2 "--out: must not be empty" -- "$js" run "$dir/threads.json" --out ""
mkfifo "$dir/scene.fifo"
expect 3 "scene.fifo: not a regular file" -- "$js" run "$dir/scene.fifo" --check
mkfifo "$dir/mesh.fifo"
scene fifo_mesh.json '{"obj": "mesh.fifo"}' "$static"
expect 3 "/actors/0/shape/obj: $dir/mesh.fifo: not a regular file" -- "$js" run "$dir/fifo_mesh.json" --check
scene zero_mesh.json '{"obj": "/dev/zero"}' "$static"
expect 3 "/actors/0/shape/obj: /dev/zero: not a regular file" -- "$js" run "$dir/zero_mesh.json" --check
head -c 100000 /dev/urandom >"$dir/garbage.obj"
scene garbage.json '{"obj": "garbage.obj"}' "$static"
expect 3 "garbage.obj:" -- "$js" run "$dir/garbage.json" --check
expect 3 "/dev/zero: not a regular file" -- "$js" render /dev/zero --png "$dir/zero.png"
mkfifo "$dir/frames.pvd"
expect 3 "frames.pvd: not a regular file" -- "$js" render "$dir" --png "$dir/fifo.png"
expect 2 "--width: Value -5 not in range 16 to 8192" -- "$js" render "$dir" --png "$dir/w.png" --width -5
expect 2 "--supersample: width x height x supersample^2 = 268435456 samples, too many (at most 67108864)" -- \
  "$js" render "$dir" --png "$dir/w.png" --width 2048 --height 2048 --supersample 8
expect 3 "--mesh: '4294967300x1' is not N1xN2 with counts from 1 to 100000" -- "$js" validate cantilever-end-shear --mesh 4294967300x1
expect 3 "--mesh: 100000x100000 gives 10000200001 vertices, too many (at most 4000000)" -- \
  "$js" validate cantilever-end-shear --mesh 100000x100000
expect 3 "--mesh: '8x' is not N1xN2" -- "$js" validate cantilever-end-shear --mesh 8x
expect 3 "--mesh: 1x2 is too coarse for slit-ring-page (at least 1x3)" -- "$js" validate slit-ring-page --mesh 1x2
expect 3 "--plots: /dev/null: cannot create the directory" -- "$js" validate cantilever-end-shear --plots /dev/null
# An output file that cannot be written is refused before the work, not after it.
expect 2 "--json: /tmp: not a regular file" -- "$js" bench statics --json /tmp
expect 3 "--json: /tmp: not a regular file" -- "$js" validate cantilever-end-shear --no-plot --json /tmp
expect 3 "--json: /tmp: not a regular file" -- "$js" stress --quick --only no-such-cell --json /tmp
# validate's --json may name a file in the --plots directory it creates.
if ! "$js" validate cantilever-end-shear --plots "$dir/plots" --json "$dir/plots/results.json" >/dev/null 2>&1 ||
  [ ! -s "$dir/plots/results.json" ]; then
  echo "FAIL: validate --json into the --plots directory it creates"
  failures=$((failures + 1))
fi
if ! "$js" stress --quick --only no-such-cell --out "$dir/stress" --json "$dir/stress/cells.json" >/dev/null 2>&1 ||
  [ ! -s "$dir/stress/cells.json" ]; then
  echo "FAIL: stress --json into the --out directory it creates"
  failures=$((failures + 1))
fi
expect 2 "--json: /nonexistent/x.json: cannot write (no directory '/nonexistent')" -- \
  "$js" bench elements --json /nonexistent/x.json
expect 2 "--png: /dev/null: not a regular file" -- "$js" render x.vtu --png /dev/null
expect 2 "--steps: Value 0 not in range 1 to 10000000" -- "$js" run examples/cantilever_strip.json --steps 0
expect 2 "--reference-iterations: Value 0 not in range 1 to 1000" -- "$js" bench contact --reference-iterations 0
expect 2 "--evaluator: x not in {scene,perFace,staged}" -- "$js" bench contact --evaluator x
expect 2 "--projection: not with --term hinge" -- "$js" bench elements --term hinge --projection clamp
expect 2 "--term stage-jets: takes --n, --repeats and --json only" -- "$js" bench elements --term stage-jets --staged
expect 2 "--garment: not with --term midedge, which runs on the grid only" -- "$js" bench elements --term midedge --garment 4
expect 2 "--garment: Value 41 not in range 1 to 40" -- "$js" bench elements --garment 41
expect 2 "--checkpoint-every: Value 99999999999 not in range 1 to 10000000" -- \
  "$js" run examples/cantilever_strip.json --checkpoint-every 99999999999
expect 3 "cantilever-end-moment, slit-ring-page, slit-ring-page-relaxation, hinged-cylindrical-roof)" -- \
  "$js" validate slit-plate
expect 3 "--grading: 'x' is not one of: uniform, cosine" -- "$js" validate slit-annular-plate --grading x
expect 3 "--linear-solver: linear solver 'x': expected auto, cholmod, ldlt or pcg" -- "$js" validate slit-annular-plate --linear-solver x
# Real-valued options refuse NaN and infinities where they enter (CLI11's PositiveNumber and Range let NaN through).
expect 2 "--load: nan: must be a finite number > 0" -- "$js" validate hinged-cylindrical-roof --load nan
expect 2 "--thickness: 1e300: must be a finite number > 0 and at most 1000" -- \
  "$js" validate hinged-cylindrical-roof --thickness 1e300
expect 2 "--path-increment: nan: must be a finite number in" -- \
  "$js" validate hinged-cylindrical-roof --path-increment nan
expect 2 "--max-forcing: nan: must be a finite number in" -- "$js" bench solver --max-forcing nan
expect 2 "--residual-tolerance: 5: must be a finite number > 0 and at most 0.1" -- "$js" validate cantilever-end-shear --residual-tolerance 5
expect 2 "--dt: inf: must be a finite number > 0" -- "$js" bench solver --dt inf
expect 2 "--residual-tolerance: -nan: must be a finite number > 0" -- "$js" validate slit-annular-plate \
  --residual-tolerance -nan
expect 2 "--azimuth: nan: must be a finite number in [-360, 360]" -- \
  "$js" render "$dir" --png "$dir/a.png" --azimuth nan
expect 2 "--range: MIN must be below MAX" -- "$js" render "$dir" --png "$dir/r.png" --range 1 0
expect 2 "--frame: Value -1 not in range 0 to 10000000" -- "$js" render "$dir" --png "$dir/f.png" --frame -1
expect 2 "--frame: applies to a series (.pvd) or a run's output directory" -- \
  "$js" render "$dir/x.vtu" --png "$dir/f.png" --frame 1
expect 2 "--tol-fd: nan: must be a finite number > 0" -- "$js" check-derivatives --term membrane --tol-fd nan
expect 2 "--fd-initial-step: 1e308: must be a finite number > 0 and at most 1" -- \
  "$js" check-derivatives --term membrane --fd-initial-step 1e308
expect 2 "--fold-min-delta: 10: must be a finite number > 0 and at most 3.14159" -- \
  "$js" check-derivatives --term bending --fold-min-delta 10
expect 2 "--fold-min-delta: must not exceed --fold-max-delta" -- \
  "$js" check-derivatives --term bending --fold-min-delta 0.5 --fold-max-delta 0.1

# A FIFO given to bench dynamics --replot blocked its read; a checkpoint of nested CBOR arrays crashed --resume.
expect 3 "frames.pvd: not a regular file (a directory, FIFO or device): cannot read it as a bench dynamics" -- \
  "$js" bench dynamics --replot "$dir/frames.pvd" --png "$dir/replot.png"
mkdir "$dir/nested"
head -c 2000000 /dev/zero | tr '\0' '\201' >"$dir/nested/checkpoint.cbor"
expect 3 "checkpoint.cbor: not a jetshell checkpoint" -- \
  "$js" run "$(dirname "$0")/../../examples/hanging_cloth.json" --resume "$dir/nested" -o "$dir/nested" -q
if [ "$failures" -ne 0 ]; then
  echo "$failures hostile command-line case(s) failed"
  exit 1
fi
echo "all hostile command-line cases exit with their code and message"
