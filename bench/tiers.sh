#!/usr/bin/env bash
# Scan speed of both execution tiers (docs/performance.md, "Tiers"):
# per-instruction time of `softplc run` as (t(510 scans) - t(10 scans)) /
# (500 x instructions), so loading and compiling cancel; hyperfine (Debian
# package) times each command, the minimum of its runs is used.
#   bench/tiers.sh [RUNS]      (after a release build of softplc)
set -euo pipefail
cd "$(dirname "$0")/.."
runs=${1:-10}
bin=${CARGO_TARGET_DIR:-target}/release/softplc
dir=$(mktemp -d)
trap 'rm -rf "$dir"' EXIT
cargo run --quiet --release -p softplc-core --example bench_programs -- "$dir" > "$dir/list"
min() { python3 -c 'import json,sys; print(min(json.load(open(sys.argv[1]))["results"][0]["times"]))' "$1"; }
printf '%-12s %-7s %12s %14s\n' program tier ns/instr compile
while read -r file n; do
  for tier in interp jit; do
    for scans in 10 510; do
      hyperfine -N --style none --warmup 1 --runs "$runs" --export-json "$dir/$scans.json" \
        "$bin run $file --scans $scans --exec $tier" > /dev/null
    done
    ns=$(python3 -c "print(f'{($(min "$dir/510.json") - $(min "$dir/10.json")) / (500 * $n) * 1e9:.3f}')")
    compile=$("$bin" check "$file" --exec "$tier" --stats 2>&1 >/dev/null | sed -n 's/.*compiled in //p')
    printf '%-12s %-7s %12s %14s\n' "$(basename "$file" .il)" "$tier" "$ns" "${compile:--}"
  done
done < "$dir/list"
