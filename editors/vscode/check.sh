#!/usr/bin/env sh
# The extension as a user builds it (README.md): install the locked dependencies, type-check and
# bundle, test the grammar under VS Code's engine and the bundle, package the .vsix, and check that
# the package holds the bundle and the grammar and no node_modules. CI runs it (.ci/run).
set -eu
cd "$(dirname "$0")"
npm ci --no-audit --no-fund --loglevel=error
npm run --silent compile
npm test --silent
rm -f fmsvm.vsix
npm run --silent package > /dev/null
python3 - fmsvm.vsix <<'PY'
import sys, zipfile
names = zipfile.ZipFile(sys.argv[1]).namelist()
for needed in ("extension/out/extension.js", "extension/syntaxes/fanuc-macro.tmLanguage.json",
               "extension/package.json", "extension/language-configuration.json"):
    assert needed in names, (needed, names)
assert not any("node_modules" in n for n in names), names
assert len(names) <= 10, names
print("vsix: %d files, the bundle and the grammar, no node_modules" % len(names))
PY
