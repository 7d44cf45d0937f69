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

venv_ok() { [ -x "$py" ] && "$py" -c 'import can, canopen, matplotlib, pytest, dtctune' 2>/dev/null; }
if ! venv_ok; then
    # A fresh clone: create the venv as the README's commands do (idempotent; the lock keeps
    # two tests started together from building it twice).
    echo "run_python_test: creating .venv with tools/setup_venv.sh" >&2
    if ! flock "$repo/.venv.lock" "$repo/tools/setup_venv.sh" >&2 || ! venv_ok; then
        echo "The Python venv .venv with dtctune and its packages is missing or incomplete and" >&2
        echo "tools/setup_venv.sh could not create it (see above; it needs python3-venv and PyPI)." >&2
        exit 1
    fi
fi
cd "$repo"
export MPLBACKEND=Agg
if [ -n "$uml" ]; then
    exec "$repo/tests/can/uml/run_in_uml.sh" --timeout "$uml" -- "$py" -m pytest -p no:cacheprovider --color=no "$@"
fi
exec "$py" -m pytest -p no:cacheprovider "$@"
