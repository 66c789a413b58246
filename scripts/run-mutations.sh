#!/usr/bin/env bash
# Mutation testing (issue 12): changes one formula at a time in a copy of the source
# (build-mutate/), rebuilds, runs the tests and writes docs/mutation.md. Exits 1 when a mutation
# survives. Options: --only TEXT..., --list (see Testing/Mutation/plod_mutate.py).
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/install-deps.sh
exec xvfb-run -a -s "-screen 0 1280x1024x24 -noreset" /usr/bin/python3 Testing/Mutation/plod_mutate.py "$@"
