#!/usr/bin/env bash
# Validate the generated FMU's modelDescription.xml against the official
# FMI 2.0 XSD. Exit 77 (CTest: skipped) when the schema folder is absent.
set -euo pipefail
fmu=$1
schema_dir=${PCS_SHARED_DIR:-${2:-}}
xsd="$schema_dir/fmi2-schema/fmi2ModelDescription.xsd"
if [ -z "$schema_dir" ] || [ ! -f "$xsd" ]; then
  echo "skipped: FMI 2.0 XSD not found (configure with -DPCS_SHARED_DIR=... or set PCS_SHARED_DIR)"
  exit 77
fi
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
unzip -q -o "$fmu" modelDescription.xml -d "$tmp"
xmllint --noout --schema "$xsd" "$tmp/modelDescription.xml"
# The FMU's layout as the standard requires it.
listing=$(unzip -Z1 "$fmu")
model=$(sed -n 's/.*modelIdentifier="\([^"]*\)".*/\1/p' "$tmp/modelDescription.xml" | head -1)
for entry in modelDescription.xml "binaries/linux64/$model.so" resources/ports.cfg documentation/externalDependencies.txt; do
  grep -qx "$entry" <<<"$listing" || { echo "missing $entry in $fmu"; exit 1; }
done
echo "ok: $fmu validates against $xsd"
