#!/usr/bin/env bash
# Runs the default reproduce and every committed mission suite with the binary BINARY into
# FOLDER, for docs/probes/same_results.py to compare two such folders (before and after a
# change that must not move a result).
# usage: docs/probes/same_results.sh BINARY FOLDER
set -euo pipefail
bin=$(realpath "$1")
mkdir -p "$2"
out=$(realpath "$2")
cd "$(dirname "$0")/../.."
"$bin" reproduce --out "$out/reproduce" > "$out/reproduce.log"
for suite in missions missions-competence missions-contexts missions-offer; do
    "$bin" run "docs/results/$suite/config.ron" --out "$out/$suite" > "$out/$suite.log"
done
