#!/usr/bin/env bash
# SPDX-License-Identifier: GPL-3.0-or-later
# End-to-end test of a sharded retrieval run through the CLI: `canonform stage` one stage and one
# shard at a time gives the bytes of `canonform retrieve`; `canonform status` tells what is done;
# a deleted shard output is redone, and only it.
#   sharded_test.sh CANONFORM WORKDIR
set -u
cf=$(realpath "$1"); work=$2
. "$(dirname "$0")/lib.sh"
rm -rf "$work"; mkdir -p "$work"; cd "$work" || exit 1

echo "canonform stage / status, end to end"
"$cf" generate --collection coll --vertices 600 --poses 3 --classes standard,long-arms 2> gen.err
check "a generated collection" test -s coll/labels.csv
opts=(--method none --words 30 --seed 3)
"$cf" retrieve --dataset coll --out one "${opts[@]}" > one.out 2> one.err
check "retrieve on one machine" test -s one/none/distances.bin

check "stage init" "$cf" stage init --dataset coll --out run --shards 3 --blocks 2 "${opts[@]}"
"$cf" status run > st0.txt
check "status of a new run: everything pending" grep -q "| features | 3 | 0 | - | 0,1,2 |" st0.txt
"$cf" stage codebook run > cb.out 2>&1
check "a stage before its inputs: exit 1, naming the missing parts" \
  bash -c "[ $? -eq 1 ] && grep -q 'needs the features parts 0,1,2 first' cb.out"
for i in 0 1 2; do "$cf" stage features run --shard $i --threads 1 2>> stages.err; done
"$cf" status run --json > st1.json
check "status --json: features done, codebook pending" \
  json st1.json "j['stages'][0]['done'] == [0, 1, 2] and j['stages'][1]['pending'] == [0] and not j['complete']"
"$cf" stage codebook run 2>> stages.err
for i in 0 1 2; do "$cf" stage histograms run --shard $i 2>> stages.err; done
for i in 0 1; do "$cf" stage distances run --shard $i 2>> stages.err; done
"$cf" stage merge run 2>> stages.err
for f in distances.bin metrics.json models.csv pr.csv; do
  check "sharded $f is byte-identical to retrieve's" cmp -s run/none/$f one/none/$f
done
"$cf" status run > st2.txt
check "status: complete" grep -qx "complete" st2.txt
"$cf" stage features run --shard 1 2> again.err
check "a done stage is not redone" grep -q "already done" again.err

rm -f run/none/forms/standard_2.ply
"$cf" status run > st3.txt
check "a deleted output: its shard is pending again" grep -q "| features | 3 | 2 | - | 1 |" st3.txt
"$cf" stage all run 2> all.err
check "stage all redoes only that shard" bash -c "[ \$(grep -c 'done in' all.err) -eq 1 ] && grep -q '\[features 1/3\]' all.err"
check "the output is back" test -s run/none/forms/standard_2.ply
check "the result is unchanged" cmp -s run/none/distances.bin one/none/distances.bin
"$cf" stage features run --shard 3 > bad.out 2>&1
check "a shard out of range: exit 1" bash -c "[ $? -eq 1 ] && grep -q 'parts 0 to 2' bad.out"
"$cf" status nothere > bad2.out 2>&1
check "status of a folder that is no run: exit 1" bash -c "[ $? -eq 1 ] && grep -q 'not a sharded run' bad2.out"

# index and query: a member of the collection finds itself first, in the matrix row's order.
check "index the sharded run" "$cf" index run
m=$(ls coll/*.ply coll/*/*.ply 2>/dev/null | head -2 | tail -1)
name=$(basename "${m%.*}")
"$cf" query run "$m" --top 4 --json > q.json 2> q.err
check "query: the member itself first, at distance 0, then three others" json q.json "j['matches'][0]['name'] == '$name' and j['matches'][0]['distance'] == 0 and len(j['matches']) == 4 and j['models'] == 6"
check "query: the order of the distance matrix row" /usr/bin/python3 -c "
import json, struct, sys
q = json.load(open('q.json')); names = [l.split(',')[0] for l in open('run/none/models.csv').read().split()[1:]]
n = len(names); d = struct.unpack('%df' % (n * n), open('run/none/distances.bin', 'rb').read())
k = names.index('$name'); row = sorted(range(n), key=lambda c: (d[k * n + c], c))
sys.exit(0 if [names[c] for c in row[:4]] == [x['name'] for x in q['matches']] else 1)"
"$cf" query run "$m" --top 2 > q.txt
check "query: a text answer" grep -q "^   1  $name " q.txt
check "query: a small index is searched exhaustively" json q.json "j['search'] == 'exhaustive' and j['candidates'] == 6"
"$cf" query run "$m" --top 4 --candidates 3 --json > q2.json 2> q2.err
check "query --candidates: two stages, exact distances of the candidates" json q2.json "j['search'] == 'two-stage' and j['candidates'] == 4 and len(j['matches']) == 4 and j['matches'][0]['name'] == '$name' and j['matches'][0]['distance'] == 0"
"$cf" query run "$m" --top 4 --candidates 3 --exact --json > q3.json 2> q3.err
check "query --exact: every model, the answer of the default query" /usr/bin/python3 -c "
import json, sys
a = json.load(open('q.json')); b = json.load(open('q3.json'))
sys.exit(0 if b['search'] == 'exhaustive' and a['matches'] == b['matches'] else 1)"

# Evaluation without the matrix: each model's nearest through the index; the measures equal retrieve's.
check "stage init --evaluation neighbours" "$cf" stage init --dataset coll --out nb --shards 2 --blocks 2 --evaluation neighbours "${opts[@]}"
"$cf" stage all nb 2> nb.err
check "neighbours: an index stage, no distance matrix" bash -c "test -s nb/none/index.cfci && test -s nb/none/neighbours.bin && ! test -e nb/none/distances.bin"
check "neighbours: NN, tiers, E-measure and (no truncation at 5 of 5) DCG equal retrieve's" /usr/bin/python3 -c "
import json, sys
a = json.load(open('nb/none/metrics.json')); b = json.load(open('one/none/metrics.json'))
keys = ['nn', 'first_tier', 'second_tier', 'e_measure', 'dcg', 'queries']
sys.exit(0 if a['evaluation'] == 'neighbours' and all(a[m][k] == b[m][k] for m in ('micro', 'macro') for k in keys) else 1)"
"$cf" status nb > nbst.txt
check "status: the index stage of a neighbours run" grep -q "| index | 1 | 1 | - | - |" nbst.txt

# canonform slurm without --submit: the scripts only (the cluster run is tests/e2e/slurm_test.sh).
"$cf" slurm --dataset coll --out sl --shards 4 --blocks 2 --method none --partition short --time 00:05:00 \
  --cpus-per-task 2 --mem 3G --max-parallel 2 > sl.out 2> sl.err
check "slurm: one script per stage" bash -c "ls sl/slurm/{features,codebook,histograms,distances,merge}.sbatch > /dev/null"
check "slurm: features as a job array over the shards, with the options" bash -c "grep -qx '#SBATCH --array=0-3%2' sl/slurm/features.sbatch && grep -qx '#SBATCH --partition=short' sl/slurm/features.sbatch && grep -qx '#SBATCH --cpus-per-task=2' sl/slurm/features.sbatch && grep -qx '#SBATCH --mem=3G' sl/slurm/features.sbatch && grep -q 'stage features .* --shard \"\$SLURM_ARRAY_TASK_ID\"' sl/slurm/features.sbatch"
check "slurm: distances over the blocks, merge a single job" bash -c "grep -qx '#SBATCH --array=0-1%2' sl/slurm/distances.sbatch && ! grep -q 'array' sl/slurm/merge.sbatch"
check "slurm: the scripts are valid bash" bash -c "for f in sl/slurm/*.sbatch; do bash -n \$f || exit 1; done"
finish
