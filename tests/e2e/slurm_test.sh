#!/usr/bin/env bash
# SPDX-License-Identifier: GPL-3.0-or-later
# End-to-end test of `canonform slurm` on a one-node Slurm cluster of this machine
# (tools/slurm_cluster.sh): a sharded run through the scheduler gives the bytes of the local
# `canonform retrieve`; a shard's job killed mid-way (scancel) and the run submitted again: only
# that shard is redone, the result is unchanged. The cluster is stopped at the end, also on failure.
#   slurm_test.sh SOURCE_DIR CANONFORM WORKDIR      (exit 77: skipped - not root, or no Slurm)
set -u
src=$(realpath "$1"); cf=$(realpath "$2"); work=$3
. "$(dirname "$0")/lib.sh"
if [ "$(id -u)" -ne 0 ] || ! command -v slurmctld > /dev/null || ! command -v munged > /dev/null; then
  echo "skipped: needs root and Debian's slurm-wlm and munge (tools/setup.sh)"
  exit 77
fi
rm -rf "$work"; mkdir -p "$work"; cd "$work" || exit 1
work=$(pwd)
cluster="$work/cluster"
trap '"$src/tools/slurm_cluster.sh" stop "$cluster"' EXIT
echo "canonform slurm, end to end, on a one-node cluster"
"$src/tools/slurm_cluster.sh" start "$cluster" > cluster.out 2> cluster.err || { cat cluster.err; fail "start the cluster"; finish; exit 1; }
export SLURM_CONF="$cluster/slurm.conf"
pass "start the cluster"

# wait_jobs SECONDS: until no job is queued or running (fails after SECONDS).
wait_jobs() {
  local t=0
  while [ -n "$(squeue -h -o %i 2>/dev/null)" ]; do
    sleep 1; t=$((t + 1))
    if [ $t -ge "$1" ]; then squeue; return 1; fi
  done
  return 0
}

"$cf" generate --collection coll --vertices 600 --poses 3 --classes standard,long-arms,short-legs 2> gen.err
opts=(--method none --words 30 --seed 5)
"$cf" retrieve --dataset coll --out one "${opts[@]}" > one.out 2> one.err
check "retrieve on this machine" test -s one/none/distances.bin

"$cf" slurm --dataset coll --out run --shards 3 --blocks 2 "${opts[@]}" --time 00:10:00 --submit > sub1.out 2> sub1.err
check "submitted: one job per stage" bash -c "[ \$(wc -l < sub1.out) -eq 5 ] && grep -q '^features [0-9]* 0,1,2$' sub1.out"
check "the jobs finish" wait_jobs 120
check "status: complete" bash -c "'$cf' status run | grep -qx complete"
for f in distances.bin metrics.json models.csv; do
  check "through Slurm, $f is byte-identical to the local run" cmp -s run/none/$f one/none/$f
done
check "a job log per part" test -s "$(ls run/slurm/logs/features_1_*.out | head -1)"

# Kill shard 1's job mid-way: one part at a time (--max-parallel 1), so shard 1 runs alone. A
# shard of three small models takes about a second, so scancel may land after the shard wrote its
# marker (stages/features_1.json, written last): then the shard is done, which is right but not
# the case under test, and the scenario is tried again on a new run folder (at most 3 times).
killed=0; run2=
for attempt in 1 2 3; do
  run2=run2_$attempt
  "$cf" slurm --dataset coll --out $run2 --shards 3 --blocks 2 "${opts[@]}" --max-parallel 1 --submit > sub2.out 2> sub2.err
  job=$(awk '$1 == "features" {print $2}' sub2.out)
  killed=0
  for _ in $(seq 600); do
    if squeue -h -r -t R -o %i | grep -qx "${job}_1"; then scancel "${job}_1"; killed=1; break; fi
    sleep 0.1
  done
  wait_jobs 90 || break
  [ $killed -eq 1 ] && [ ! -e $run2/stages/features_1.json ] && break
  echo "  (attempt $attempt: shard 1 finished before scancel reached it; again)"
  killed=0
done
check "shard 1's job killed while it ran" [ $killed -eq 1 ]
check "the jobs after it are cancelled (afterok never holds)" wait_jobs 90
"$cf" status $run2 > st.txt
check "status: features shard 1 pending, the others done" grep -q "| features | 3 | 2 | - | 1 |" st.txt
t0=$(stat -c %Y.%N $run2/stages/features_0.json $run2/stages/features_2.json)
"$cf" slurm --dataset coll --out $run2 --shards 3 --blocks 2 "${opts[@]}" --submit > sub3.out 2> sub3.err
check "resubmitted: features only for shard 1" grep -q "^features [0-9]* 1$" sub3.out
check "the jobs finish" wait_jobs 120
check "status: complete" bash -c "'$cf' status $run2 | grep -qx complete"
check "shards 0 and 2 were not redone" [ "$t0" = "$(stat -c %Y.%N $run2/stages/features_0.json $run2/stages/features_2.json)" ]
check "the result is unchanged" cmp -s $run2/none/distances.bin one/none/distances.bin
check "metrics unchanged" cmp -s $run2/none/metrics.json one/none/metrics.json
"$cf" slurm --dataset coll --out $run2 --shards 3 --blocks 2 "${opts[@]}" --submit > sub4.out 2> sub4.err
check "a complete run submits nothing" grep -q "nothing to submit" sub4.out
finish
