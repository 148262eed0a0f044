#!/usr/bin/env bash
# SPDX-License-Identifier: GPL-3.0-or-later
# Runs one libFuzzer target for a bounded time and fails on any finding (crash, sanitizer report,
# leak, timeout, out-of-memory), whose input is kept in FINDINGS/ with the report.
#   run_fuzz.sh TARGET SEEDS CORPUS FINDINGS SECONDS [libFuzzer options...]
# Inputs, so that each run extends the last one instead of starting over:
#   - tests/fuzz/corpus/NAME/ (NAME = the target without "fuzz_"): the corpus kept in the repository,
#     minimised with libFuzzer's -merge=1 and capped; read only here. tools/fuzz_corpus.sh folds
#     what runs found (CORPUS) back into it, and a developer commits it;
#   - SEEDS: the files the unit tests wrote (valid outputs of the writers, bad-input cases);
#   - CORPUS: this build's working corpus (new inputs land here).
set -u
target=$1 seeds=$2 corpus=$3 findings=$4 seconds=$5
shift 5
name=$(basename "$target"); name=${name#fuzz_}
kept=$(cd "$(dirname "$0")" && pwd)/corpus/$name
mkdir -p "$seeds" "$corpus" "$findings"
dirs=("$corpus" "$seeds")
[ -d "$kept" ] && dirs+=("$kept")
log="$findings/last_run.log"
# -rss_limit_mb: a reader that allocates what a lying header claims is a finding; -timeout: a hang is.
# Leaks are findings too (LeakSanitizer, on by default with ASan).
export ASAN_OPTIONS=${ASAN_OPTIONS:-abort_on_error=1:detect_leaks=1} UBSAN_OPTIONS=${UBSAN_OPTIONS:-print_stacktrace=1:halt_on_error=1}
# The target's file round trips write into a folder of the build, removed afterwards.
export CANONFORM_FUZZ_SCRATCH="$findings/scratch.$$"
"$target" -max_total_time="$seconds" -timeout=20 -rss_limit_mb=2048 -max_len=65536 -print_final_stats=1 \
  -artifact_prefix="$findings/" "$@" "${dirs[@]}" > "$log" 2>&1
rc=$?
rm -rf "$CANONFORM_FUZZ_SCRATCH"
runs=$(grep -o 'stat::number_of_executed_units: *[0-9]*' "$log" | grep -o '[0-9]*$')
cov=$(grep -o 'cov: [0-9]*' "$log" | tail -1)
if [ $rc -ne 0 ]; then
  grep -E "ERROR|SUMMARY|==[0-9]+==|runtime error|fuzz:" "$log" | head -20
  echo "$name: FINDING after ${runs:-?} runs (exit $rc); input and report in $findings/"
  exit 1
fi
echo "$name: ${runs:-?} runs in ${seconds} s, ${cov:-cov ?}, $(ls "$kept" 2>/dev/null | wc -l) kept inputs + $(ls "$seeds" | wc -l) seeds, no finding"
