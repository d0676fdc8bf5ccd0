#!/usr/bin/env bash
# Regenerates src/record/foxglove/*.json, the Foxglove schemas novanc writes into its
# recordings (docs/recording.md, "Foxglove topics"), from the published @foxglove/schemas npm
# package (its JSON Schemas, `@foxglove/schemas/jsonschema`). The version is the one
# .ci/run installs for the test that checks the copies against the package
# (tests/record_foxglove.rs).
set -euo pipefail
cd "$(dirname "$0")/.."
VERSION=2.1.0
DIR=target/foxglove-schemas
npm install --silent --prefix "$DIR" "@foxglove/schemas@$VERSION" >/dev/null
for s in SceneUpdate FrameTransform Log; do
  node -e '
    const s = require(process.argv[1] + "/node_modules/@foxglove/schemas/jsonschema")[process.argv[2]];
    process.stdout.write(JSON.stringify(s) + "\n");
  ' "$PWD/$DIR" "$s" > "src/record/foxglove/$s.json"
done
