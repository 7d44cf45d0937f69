#!/usr/bin/env bash
# ctest entry for the Python tests: check the venv, then run pytest with it, either
# directly (tool unit tests) or inside User-Mode Linux (tests that need SocketCAN).
#
#   tests/can/run_python_test.sh [--uml SECONDS] -- PYTEST_ARGS...
set -uo pipefail
repo=$(cd "$(dirname "${BASH_SOURCE[0]}")/../.." && pwd)
py="$repo/.venv/bin/python"
uml=""
if [ "${1:-}" = "--uml" ]; then
    uml=${2:?--uml needs a time limit in seconds}
    shift 2
fi
[ "${1:-}" = "--" ] && shift

if [ ! -x "$py" ] || ! "$py" -c 'import can, canopen, matplotlib, pytest, dtctune' 2>/dev/null; then
    echo "The Python venv .venv with dtctune and its packages is missing or incomplete:" >&2
    echo "run tools/setup_venv.sh (or tools/install-deps.sh, see README.md), then run ctest again." >&2
    exit 1
fi
cd "$repo"
export MPLBACKEND=Agg
if [ -n "$uml" ]; then
    exec "$repo/tests/can/uml/run_in_uml.sh" --timeout "$uml" -- "$py" -m pytest -p no:cacheprovider --color=no "$@"
fi
exec "$py" -m pytest -p no:cacheprovider "$@"
