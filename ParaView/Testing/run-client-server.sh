#!/usr/bin/env bash
# Client-server test: `mpiexec -np 2 pvserver` on a free local port, and a client (ParaView's
# Python package run by /usr/bin/python3: Debian's pvpython would find VTK 9.1's vtkmodules
# first) that connects, shows the generated scene with the Perceptual LOD representation and
# checks the image it receives. Usage: run-client-server.sh <mpiexec> <pvserver> <script> <out>
set -uo pipefail
mpiexec="$1" pvserver="$2" script="$3" out="$4"
port="$(/usr/bin/python3 -c 'import socket; s = socket.socket(); s.bind(("localhost", 0)); print(s.getsockname()[1])')"
log="$out/pvserver.log"
"$mpiexec" -np 2 "$pvserver" --server-port="$port" > "$log" 2>&1 &
server=$!
for _ in $(seq 1 120); do
  grep -q "Accepting connection" "$log" 2>/dev/null && break
  sleep 0.5
done
/usr/bin/python3 "$script" client "$out" "$port"
status=$?
kill "$server" 2>/dev/null
wait "$server" 2>/dev/null
exit $status
