#!/bin/sh
# The camera benchmark (issue 6): 2048 x 2048 Mono16 from the simulated GigE Vision camera over
# loopback. A receive buffer of 32 MiB needs net.core.rmem_max raised, which only root can do
# (the kernel caps a socket's buffer there); without it the figures show what a default host gets.
set -e
cd "$(dirname "$0")/.."
if [ "$(id -u)" = 0 ]; then sysctl -qw net.core.rmem_max=33554432; fi
echo "net.core.rmem_max = $(cat /proc/sys/net/core/rmem_max)"
exec tests/run_in_netns.sh build/tests/bench_camera "$@"
