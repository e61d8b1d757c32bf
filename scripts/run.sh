#!/usr/bin/env bash
# Sets up the machine, builds sinkwatch and runs the main job on its embedded
# default. This is the README's first command.
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/setup.sh >&2
cmake --preset default >/dev/null
cmake --build --preset default --target sinkwatch >&2
exec ./build/default/ground/cli/sinkwatch "${@:-replay}"
