#!/usr/bin/env bash
# The README's first command: install what is missing, build, and run the main
# job on the embedded default: simulate a 2D grid world with ground truth,
# optimize it from the dead-reckoning guess, and report the error against the
# truth. Outputs go to out/demo/.
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/install_deps.sh
bash scripts/build.sh
mkdir -p out/demo
./build/apps/slam simulate -o out/demo
./build/apps/slam optimize -i out/demo/graph.g2o -o out/demo/optimized.g2o \
  --gt out/demo/ground_truth.tum --plot out/demo/plots \
  --report out/demo/report.json
echo
echo "demo outputs in out/demo/: graph.g2o (noisy input), optimized.g2o,"
echo "report.json (chi2, timings, ATE/RPE) and plots/*.png"
