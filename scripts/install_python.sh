#!/usr/bin/env bash
# Installs the Python package (`import grapebench`, docs/python.md) into a virtual
# environment or the system Python: builds it with scripts/setup.sh (Debian packages,
# no Python index), then copies the build's package (build/python/grapebench: the
# extension and its Python files) into the interpreter's site-packages.
# Usage: scripts/install_python.sh [--venv DIR]   a venv at DIR (made if missing, with
#                                                 Debian's numpy and pandas visible)
#        scripts/install_python.sh --system       /usr/bin/python3's site-packages
# GRAPEBENCH_BUILD_DIR: the build folder (default build/); GRAPEBENCH_NO_BUILD=1 installs
# what is built there without building (the package's own test).
set -euo pipefail
here="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
build="${GRAPEBENCH_BUILD_DIR:-$here/build}"
case "${1:-}" in
  --venv) [ -n "${2:-}" ] || { echo "usage: scripts/install_python.sh --venv DIR | --system" >&2; exit 2; }
          venv="$2" ;;
  --system) venv="" ;;
  *) echo "usage: scripts/install_python.sh --venv DIR | --system" >&2; exit 2 ;;
esac
[ "${GRAPEBENCH_NO_BUILD:-0}" = 1 ] || "$here/scripts/setup.sh" "$build" >/dev/null
[ -f "$build/python/grapebench/__init__.py" ] || { echo "install_python: no package in $build/python (GRAPEBENCH_BUILD_PYTHON off?)" >&2; exit 2; }
python=/usr/bin/python3
if [ -n "$venv" ]; then
  [ -x "$venv/bin/python" ] || /usr/bin/python3 -m venv --system-site-packages "$venv"
  python="$venv/bin/python"
fi
site="$("$python" -c 'import sysconfig; print(sysconfig.get_paths()["platlib"])')"
mkdir -p "$site"
rm -rf "$site/grapebench.tmp" && cp -r "$build/python/grapebench" "$site/grapebench.tmp"
find "$site/grapebench.tmp" -name __pycache__ -prune -exec rm -rf {} +
rm -rf "$site/grapebench" && mv "$site/grapebench.tmp" "$site/grapebench"
"$python" -c 'import grapebench; print("grapebench installed:", grapebench.__file__)'
