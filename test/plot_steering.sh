#!/usr/bin/env bash
# Self-check of plot_steering.py on a synthetic run: a helix-ish path with a mode change and
# three waypoints must give a PNG > 10 kB, and a CSV lacking a column must exit 2.
#   bash test/plot_steering.sh
set -euo pipefail
export PATH=/usr/bin:$PATH

here="$(cd "$(dirname "${BASH_SOURCE[0]}")/../scripts" && pwd)"
plot="$here/plot_steering.py"
tmp="$(mktemp -d)"
trap 'rm -rf "$tmp"' EXIT

passed=0
failed=0
pass() { echo "PASS: $1"; passed=$((passed + 1)); }
fail() { echo "FAIL: $1"; failed=$((failed + 1)); }

# Synthetic run: 200 samples of a helix drifting along x, climbing, cruise then buckle_turn.
python3 - "$tmp/run.csv" "$tmp/run.json" <<'EOF'
import json, math, sys
csv_path, json_path = sys.argv[1], sys.argv[2]
with open(csv_path, "w") as f:
    f.write("time,x,y,z,est_x,est_y,est_z,motor,slider,mode\n")
    for i in range(200):
        t = 0.5 * i
        x, y, z = 3e-4 * t, 2e-3 * math.sin(0.3 * t), 1.5e-4 * t + 2e-3 * math.cos(0.3 * t)
        mode = "cruise" if i < 120 else "buckle_turn"
        f.write("%g,%g,%g,%g,%g,%g,%g,%g,%g,%s\n" % (
            t, x, y, z, x + 1e-3, y - 5e-4, z + 5e-4,
            2.0 if mode == "cruise" else 0.5 * math.sin(t), 4e-3 * math.tanh(0.05 * (i - 120)), mode))
with open(json_path, "w") as f:
    json.dump({"controller": "mass_transformer", "mission": "synthetic helix", "reached": 2,
               "total": 3, "max_miss_mm": 25.0, "miss_mm": [3.0, 9.0, 25.0], "time_s": 99.5,
               "waypoints_m": [[0.01, 0.0, 0.005], [0.02, 0.0, 0.012], [0.035, 0.005, 0.02]]}, f)
EOF

if out="$("$plot" "$tmp/run.csv" --json "$tmp/run.json" --out "$tmp/run.png")" \
    && [ -f "$tmp/run.png" ] && [ "$(stat -c %s "$tmp/run.png")" -gt 10240 ]; then
  echo "$out"
  pass "synthetic run plotted ($(stat -c %s "$tmp/run.png") bytes)"
else
  fail "synthetic run: no PNG or PNG <= 10 kB"
fi

cut -d, -f1-8,10 "$tmp/run.csv" > "$tmp/no_slider.csv"
status=0
"$plot" "$tmp/no_slider.csv" --out "$tmp/bad.png" 2> "$tmp/err" || status=$?
if [ "$status" -eq 2 ] && grep -q "no_slider.csv" "$tmp/err" && ! grep -q Traceback "$tmp/err"; then
  pass "missing column exits 2: $(cat "$tmp/err")"
else
  fail "missing column gave status $status: $(cat "$tmp/err")"
fi

echo "plot_steering: $passed passed, $failed failed"
[ "$failed" -eq 0 ]
