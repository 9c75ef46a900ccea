#!/usr/bin/env bash
# Ctrl-C (SIGINT) in the middle of a dynamic run whose steps are being cut and retried: the run must stop with
# exit code 130 and leave complete files (summary.json says "interrupted", frames.pvd is closed, every probes.csv
# row is whole, no temporary file is left behind).
# Usage: interrupt_test.sh JETSHELL_BINARY SCRATCH_DIR
set -u
js=$1
dir=$2/interrupt_test
rm -rf "$dir" && mkdir -p "$dir"
cat > "$dir/scene.json" <<'SCENE'
{
  "gravity": [0, 0, -9.81],
  "actors": [{"type": "shell", "shape": {"generator": "rectangle", "width": 1, "height": 1, "nx": 8, "ny": 8},
              "material": {"youngsModulus": 1e6, "poissonRatio": 0.3, "thickness": 0.0005, "volumeDensity": 300},
              "colliderType": "None", "fixed": [{"select": [{"nearest": [0, 1, 0]}, {"nearest": [1, 1, 0]}]}],
              "probes": [{"name": "corner", "select": {"nearest": [1, 0, 0]}}]}],
  "analysis": {"type": "dynamic", "timeStep": 0.1, "duration": 1000},
  "solver": {"maxIterations": 2, "threads": 1},
  "outputs": {"png": false, "plots": false}
}
SCENE
"$js" run "$dir/scene.json" --out "$dir/out" > "$dir/stdout.txt" 2> "$dir/log.txt" &
pid=$!
# Wait until a step has been cut (the log says so), then interrupt.
for _ in $(seq 1 300); do
  grep -q "cuts)" "$dir/log.txt" 2>/dev/null && break
  sleep 0.1
done
grep -q "cuts)" "$dir/log.txt" || { echo "no step was cut"; kill -9 $pid; exit 1; }
kill -INT $pid
wait $pid
code=$?
fail() { echo "FAILED: $*"; cat "$dir/stdout.txt" "$dir/log.txt" | tail -20; exit 1; }
[ "$code" -eq 130 ] || fail "exit code $code, expected 130"
grep -q '"termination": "interrupted"' "$dir/out/summary.json" || fail "summary.json does not say interrupted"
tail -n 1 "$dir/out/frames.pvd" | grep -q '</VTKFile>' || fail "frames.pvd is not closed"
fields=$(head -n 1 "$dir/out/probes.csv" | awk -F, '{print NF}')
awk -F, -v n="$fields" 'NF != n { exit 1 }' "$dir/out/probes.csv" || fail "probes.csv has a partial row"
[ -z "$(find "$dir/out" -name '*.tmp*')" ] || fail "temporary files left behind"
echo "interrupted cleanly: exit 130, complete files"
