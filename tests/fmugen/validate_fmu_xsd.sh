#!/usr/bin/env bash
# Validate the generated FMU's modelDescription.xml against the official
# FMI XSD of its version (2.0 or 3.0). Exit 77 (CTest: skipped) when the
# schema folder is absent.
set -euo pipefail
fmu=$1
schema_dir=${PCS_SHARED_DIR:-${2:-}}
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
unzip -q -o "$fmu" modelDescription.xml -d "$tmp"
if grep -q 'fmiVersion="3.0"' "$tmp/modelDescription.xml"; then
  version=3 platform=x86_64-linux
else
  version=2 platform=linux64
fi
xsd="$schema_dir/fmi$version-schema/fmi${version}ModelDescription.xsd"
if [ -z "$schema_dir" ] || [ ! -f "$xsd" ]; then
  echo "skipped: FMI $version.0 XSD not found (configure with -DPCS_SHARED_DIR=... or set PCS_SHARED_DIR)"
  exit 77
fi
xmllint --noout --schema "$xsd" "$tmp/modelDescription.xml"
# The FMU's layout as the standard requires it.
listing=$(unzip -Z1 "$fmu")
model=$(sed -n 's/.*modelIdentifier="\([^"]*\)".*/\1/p' "$tmp/modelDescription.xml" | head -1)
for entry in modelDescription.xml "binaries/$platform/$model.so" resources/ports.cfg documentation/externalDependencies.txt; do
  grep -qx "$entry" <<<"$listing" || { echo "missing $entry in $fmu"; exit 1; }
done
echo "ok: $fmu validates against $xsd"
