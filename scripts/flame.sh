#!/usr/bin/env bash
# Flame graphs of the three paths docs/performance.md profiles: the five paper scenes'
# plans (criterion `plan/*/nelder-mead`), map plans (criterion
# `movingai_sample/plan_20/Boston_0_256/radius_0`) and a corner-to-corner plan on a prepared
# random 4096^2 map (`map-memory 4096 --plan`, preparation included: its frames are
# `PreparedMap::new` and below). Needs Linux perf (Debian's linux-perf); installs inferno
# (crates.io) when missing. Writes docs/flame/{scenes,maps,map4096}.svg.
#
#   scripts/flame.sh [SECONDS]   # seconds of sampling per criterion bench, default 10
set -euo pipefail
cd "$(dirname "$0")/.."
secs="${1:-10}"
command -v perf >/dev/null || { echo "flame.sh: needs perf (apt-get install linux-perf)" >&2; exit 2; }
command -v inferno-flamegraph >/dev/null || cargo install inferno --locked
out=docs/flame
tmp="$(mktemp -d)"
trap 'rm -rf "$tmp"' EXIT
exe() { # the executable of bench $1
  cargo bench -p homospline-benches --bench "$1" --no-run --message-format=json 2>/dev/null |
    python3 -c 'import json,sys
for l in sys.stdin:
    m=json.loads(l)
    if m.get("reason")=="compiler-artifact" and m.get("executable") and m["target"]["name"]==sys.argv[1]: print(m["executable"])' "$1"
}
cargo build --release -p homospline-benches --bin map-memory
profile() { # name, title, command...
  local name="$1" title="$2"; shift 2
  perf record -q -F 499 --call-graph dwarf,16384 -o "$tmp/$name.data" -- "$@" >/dev/null
  perf script -i "$tmp/$name.data" 2>/dev/null | inferno-collapse-perf >"$tmp/$name.folded"
  cp "$tmp/$name.folded" "target/flame-$name.folded"
  inferno-flamegraph --title "$title" --width 1600 --minwidth 1.5 <"$tmp/$name.folded" >"$out/$name.svg"
  echo "$out/$name.svg"
}
profile scenes "five paper scenes, 5 classes, Nelder-Mead (criterion plan/*/nelder-mead)" \
  "$(exe plan)" --bench --profile-time "$secs" 'nelder-mead$'
profile maps "20 Boston_0_256 scenarios, point robot, 5 classes (criterion movingai_sample)" \
  "$(exe maps)" --bench --profile-time "$secs" 'movingai_sample/plan_20/Boston_0_256/radius_0'
profile map4096 "random 4096^2 map: prepare, then plan corner to corner, 2 classes" \
  target/release/map-memory 4096 --plan
