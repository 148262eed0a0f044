#!/usr/bin/env bash
# SPDX-License-Identifier: GPL-3.0-or-later
# Does a change that moves the descriptor's outputs keep retrieval quality? Two builds of the tool
# run the same retrieval experiments and are compared query by query:
#   bench/run_quality_rule.sh OUT OLD_LABEL OLD_TOOL NEW_LABEL NEW_TOOL COLLECTION...
# COLLECTION: a labelled collection folder (labels.csv: path,class). Per build, collection and
# codebook seed (0, 1, 2): `TOOL retrieve --dataset COLLECTION --out OUT/BUILD/NAME/seedS --method
# none,euclidean-N --seed S` (the other seeds start from a hard-linked copy of the first's cache,
# so only the codebook and what follows it are made again; the builds never share a cache). Then
# per collection and method, experiments/paired_queries.py over the seeds of each build: NN and
# first tier averaged over the seeds per query, and a 95% interval of NEW - OLD by a paired
# bootstrap over the queries. The rule of issue 34: a change is kept only where every interval
# contains 0 or lies above it (its upper end is at least 0).
# OUT/rule_OLD_NEW.jsonl (OUT may hold the runs of several builds; finished runs are not made
# again): a header line, then per collection, method and measure the two builds' means, the
# difference and its interval ({"bench": "quality_rule", ..., "holds": "yes" or "no"}); the script
# prints them as a table and ends 1 when the rule fails anywhere. Environment:
# CANONFORM_QUALITY_THREADS (default 0: every core), CANONFORM_QUALITY_METHODS (default
# none,euclidean-N), CANONFORM_QUALITY_SEEDS (default "0 1 2"; more seeds average more of the
# codebook's variation out of each query's measures).
set -euo pipefail
[ $# -ge 6 ] || { sed -n 3,20p "$0" >&2; exit 2; }
out=$1 old_label=$2 old_tool=$3 new_label=$4 new_tool=$5
shift 5
here=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
threads=${CANONFORM_QUALITY_THREADS:-0}
methods=${CANONFORM_QUALITY_METHODS:-none,euclidean-N}
read -r -a seeds <<< "${CANONFORM_QUALITY_SEEDS:-0 1 2}"
[ ${#seeds[@]} -ge 1 ] || { echo "CANONFORM_QUALITY_SEEDS names no seed" >&2; exit 2; }
for t in "$old_tool" "$new_tool"; do [ -x "$t" ] || { echo "not an executable: $t" >&2; exit 2; }; done
[ "$old_label" != "$new_label" ] || { echo "the two builds need different labels" >&2; exit 2; }
for c in "$@"; do [ -f "$c/labels.csv" ] || { echo "not a labelled collection (no labels.csv): $c" >&2; exit 2; }; done
mkdir -p "$out"
rule=$out/rule_${old_label}_${new_label}.jsonl
start=$(date +%s)
for pair in "$old_label=$old_tool" "$new_label=$new_tool"; do
  label=${pair%%=*} tool=${pair#*=}
  for c in "$@"; do
    name=$(basename "$c")
    for seed in "${seeds[@]}"; do
      run=$out/$label/$name/seed$seed
      if [ -f "$run/report.md" ]; then continue; fi
      mkdir -p "$(dirname "$run")"
      if [ "$seed" != "${seeds[0]}" ] && [ ! -d "$run/cache" ]; then
        mkdir -p "$run"
        cp -al "$out/$label/$name/seed${seeds[0]}/cache" "$run/cache"
      fi
      echo "quality rule: $label $name seed $seed ($(($(date +%s) - start)) s)"
      "$tool" retrieve --dataset "$c" --out "$run" --method "$methods" --seed "$seed" --threads "$threads" \
        > "$run.log" 2>&1 || { echo "retrieve failed: $run (log: $run.log)" >&2; tail -3 "$run.log" >&2; exit 1; }
    done
  done
done
printf '{"date": "%s", "cpu": "%s", "builds": ["%s", "%s"], "collections": "%s", "methods": "%s", "seconds": %d}\n' \
  "$(date -u +%Y-%m-%dT%H:%M:%SZ)" "$(sed -n 's/^model name[[:space:]]*: //p' /proc/cpuinfo | head -1)" \
  "$old_label" "$new_label" "$(for c in "$@"; do basename "$c"; done | tr "\n" " " | sed "s/ $//")" "$methods" "$(($(date +%s) - start))" > "$rule"
fail=0
for c in "$@"; do
  name=$(basename "$c")
  for m in ${methods//,/ }; do
    python3 "$here/experiments/paired_queries.py" --json --method "$m" \
      --a "${seeds[@]/#/$out/$old_label/$name/seed}" --b "${seeds[@]/#/$out/$new_label/$name/seed}" \
      > "$out/paired.json"
    python3 - "$out/paired.json" "$name" "$old_label" "$new_label" "$(IFS=,; echo "${seeds[*]}")" >> "$rule" <<'EOF' || fail=1
import json, sys
r = json.load(open(sys.argv[1]))
holds = True
for measure, v in r["measures"].items():
    ok = v["interval"][1] >= 0
    holds = holds and ok
    print(json.dumps({"bench": "quality_rule", "old": sys.argv[3], "new": sys.argv[4], "collection": sys.argv[2],
                      "method": r["method"], "measure": measure, "queries": r["queries"], "old_mean": round(v["a"], 4),
                      "new_mean": round(v["b"], 4), "difference": round(v["difference"], 4),
                      "interval_low": round(v["interval"][0], 4),
                      "interval_high": round(v["interval"][1], 4), "holds": "yes" if ok else "no",
                      "seeds": sys.argv[5]}))
sys.exit(0 if holds else 1)
EOF
  done
done
rm -f "$out/paired.json"
python3 - "$rule" <<'EOF'
import json, sys
rows = [json.loads(l) for l in open(sys.argv[1])][1:]
print("| collection | method | measure | old | new | new - old | 95% interval | holds |")
print("|---|---|---|---|---|---|---|---|")
for r in rows:
    print(f"| {r['collection']} | {r['method']} | {r['measure']} | {r['old_mean']:.3f} | {r['new_mean']:.3f} | "
          f"{r['difference']:+.3f} | [{r['interval_low']:+.3f}, {r['interval_high']:+.3f}] | {r['holds']} |")
EOF
exit $fail
