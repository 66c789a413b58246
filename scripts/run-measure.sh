#!/usr/bin/env bash
# Measure the trade (issue 6): builds, then runs Testing/Quality/plod_measure.py over the bunny
# mesh, the merged bunny scans (when ../shared/data is there) and a generated 1M-triangle model,
# writing docs/results/ (CSV files, PNG plots, results.md). Pass --quick for the small model.
# Takes tens of minutes on 2 cores without --quick.
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/install-deps.sh
bash scripts/build.sh
PYTHONPATH=build/lib/python3/dist-packages xvfb-run -a -s "-screen 0 1280x1024x24 -noreset" \
  /usr/bin/python3 Testing/Quality/plod_measure.py --out docs/results "$@"
