#!/usr/bin/env bash
# Counts the core crate's public items as rustdoc sees them: every item reachable from the
# crate root through public modules (modules, types, functions, constants, traits, statics
# and re-exports; not fields or methods). Needs a nightly toolchain (rustdoc's JSON output).
#   bash tools/public-api.sh          # the count, by kind
#   bash tools/public-api.sh names    # and every item's path
set -euo pipefail
target=${CARGO_TARGET_DIR:-/tmp/relief-api}
CARGO_TARGET_DIR=$target cargo +nightly rustdoc -q -p relief --lib -- -Z unstable-options \
    --output-format json
python3 - "$target/doc/relief.json" "${1:-}" <<'PY'
import collections, json, sys

doc = json.load(open(sys.argv[1]))
index = doc["index"]
kinds, names = collections.Counter(), []


def walk(module_id, path):
    for item_id in index[str(module_id)]["inner"]["module"]["items"]:
        item = index.get(str(item_id))
        if item is None or item["visibility"] != "public":
            continue
        kind = next(iter(item["inner"]))
        if kind == "use":
            kinds["use"] += 1
            names.append(f"{path}::{item['inner']['use']['name']} (use)")
            continue
        kinds[kind] += 1
        names.append(f"{path}::{item['name']}")
        if kind == "module":
            walk(item_id, f"{path}::{item['name']}")


walk(doc["root"], "relief")
print(sum(kinds.values()), "public items:", dict(sorted(kinds.items())))
if sys.argv[2] == "names":
    print("\n".join(names))
PY
