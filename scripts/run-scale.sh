#!/usr/bin/env bash
# Scale benchmark (issue 10): builds, then runs build/bin/PerceptualLODScale once per size (one
# process each, so that each peak memory is its own) over generated models of 0.25M to 64M
# triangles, and writes docs/results/scale.csv. About 20 minutes on 2 cores; needs about 9 GB
# of memory at 64M. Pass sizes to run only those, e.g. `bash scripts/run-scale.sh 250000 1000000`.
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/install-deps.sh
bash scripts/build.sh
sizes=("$@")
if [ ${#sizes[@]} -eq 0 ]; then
  sizes=(250000 500000 1000000 2000000 4000000 8000000 16000000 32000000 64000000)
fi
out=docs/results/scale.csv
mkdir -p docs/results
rm -f "$out"
for n in "${sizes[@]}"; do
  echo "== $n triangles"
  # the full-resolution render is timed up to 16M triangles (llvmpipe takes seconds per frame
  # above that)
  xvfb-run -a -s "-screen 0 1280x1024x24 -noreset" \
    build/bin/PerceptualLODScale --triangles "$n" --frames 20 --full-render-limit 16000000 \
    --csv "$out"
done
echo "wrote $out"
