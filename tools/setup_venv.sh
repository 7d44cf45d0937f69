#!/usr/bin/env bash
# Create (or update) the Python venv at <repo>/.venv with the pinned packages of
# tools/requirements.txt and the dtctune package (editable). Safe to run again:
# the venv is reused and pip runs only when requirements.txt changed.
# Needs: python3 with the venv module (Debian: python3-venv) and network access to PyPI.
set -euo pipefail
repo=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
venv="$repo/.venv"
req="$repo/tools/requirements.txt"
stamp="$venv/.requirements.stamp"
python=${PYTHON:-python3}

if [ ! -x "$venv/bin/python" ]; then
  echo "setup_venv: creating $venv"
  "$python" -m venv "$venv"
fi
if [ ! -f "$stamp" ] || ! cmp -s "$req" "$stamp"; then
  echo "setup_venv: installing the pinned packages of tools/requirements.txt"
  "$venv/bin/python" -m pip install -q --upgrade pip
  "$venv/bin/python" -m pip install -q -r "$req"
  cp "$req" "$stamp"
fi
# Editable: the tool follows the sources; --no-deps: requirements.txt pins them all.
# An older install made an import hook (__editable___dtctune_*_finder.py) that every Python
# start in the venv imports; tools/pyproject.toml now gives a plain path entry: reinstall.
finder=$(ls "$venv"/lib/python3*/site-packages/__editable___dtctune_*_finder.py 2>/dev/null || true)
if [ -n "$finder" ] || ! "$venv/bin/python" -c 'import dtctune' 2>/dev/null || [ ! -x "$venv/bin/dtctune" ]; then
  echo "setup_venv: installing dtctune (editable)"
  "$venv/bin/python" -m pip install -q --no-deps -e "$repo/tools"
fi
# The `dtctune` command: pip's console script, replaced by a launcher that starts Python without
# the site module (-S). The short commands (get, set, save, list) need only the standard library
# and the dtctune package; site (the venv's .pth files, _distutils_hack, the sitecustomize search) is 0.03-0.06 s
# of each start-up inside User-Mode Linux. dtctune adds the venv's packages itself when a command
# needs python-can or matplotlib (dtctune.need_third_party).
launcher="$venv/bin/dtctune"
marker="# dtctune launcher of tools/setup_venv.sh"
if [ -L "$venv" ]; then
  # Another checkout's venv (a worktree linking it): its launcher is that checkout's business.
  echo "setup_venv: $venv is a link to another checkout's venv: its dtctune launcher is left as it is"
elif ! grep -qF "$marker" "$launcher" 2>/dev/null || ! grep -qF "$repo/tools" "$launcher"; then
  tools_literal=$("$venv/bin/python" -c 'import sys; print(repr(sys.argv[1]))' "$repo/tools")
  tmp="$launcher.tmp.$$"
  cat > "$tmp" <<LAUNCHER
#!$venv/bin/python -S
$marker (Python without site: see there)
import sys
sys.path.insert(0, $tools_literal)
from dtctune.cli import main
sys.exit(main())
LAUNCHER
  chmod +x "$tmp"
  mv -f "$tmp" "$launcher"
fi
echo "setup_venv: ready: $venv (activate with: . .venv/bin/activate)"
