#!/usr/bin/env bash
# SPDX-License-Identifier: GPL-3.0-or-later
# End-to-end tests of the canonform tool: the three commands on a generated figure, --json
# summaries, and every kind of bad input (clear message, exit 1, no output file left behind).
#   cli_test.sh CANONFORM PLYCHECK WORKDIR
set -u
cf=$(realpath "$1"); plycheck=$(realpath "$2"); work=$3
. "$(dirname "$0")/lib.sh"
experiments=$(realpath "$(dirname "$0")/../../experiments")
rm -rf "$work"; mkdir -p "$work"; cd "$work" || exit 1

echo "canonform tool, end to end"
check "generate a figure" "$cf" generate fig.ply --vertices 3000 --pose 2
"$plycheck" fig.ply > fig.json
check "figure has ~3000 vertices and faces" json fig.json "2200 < j['vertices'] < 3800 and j['faces'] > 4000"

"$cf" conformal fig.ply cf.ply --json > cf_out.json
check "conformal --json" json cf_out.json "j['vertices'] > 2000 and j['residual'] < 1e-8"
"$plycheck" cf.ply > cf.json
check "conformal factor stored as quality in [0, 1]" json cf.json "j['has_quality'] and j['quality_min'] == 0 and abs(j['quality_max'] - 1) < 1e-6"

"$cf" features fig.ply fp.ply --json > fp_out.json
check "features --json" json fp_out.json "j['feature_points'] == j['maxima'] and 6 <= j['maxima'] <= 55 and len(j['indices']) == j['feature_points']"
"$plycheck" fp.ply > fp.json
check "feature points written as a point cloud" json fp.json "j['faces'] == 0 and j['vertices'] >= 6"
"$cf" features fig.ply fpr.ply --fill random --seed 3 --json > fpr_out.json
check "features --fill random gives exactly ceil(sqrt(N))" json fpr_out.json "j['feature_points'] == __import__('math').isqrt(j['vertices'] - 1) + 1"

"$cf" canonical fig.ply canon.ply --json > canon_out.json
check "canonical --json summary" json canon_out.json "j['iterations'] > 0 and j['final_stress'] < j['initial_stress'] and j['variant'] == 'N' and j['beta'] == 130 and j['seconds'] > 0"
"$plycheck" canon.ply fig.ply > canon.json
check "canonical form keeps vertices, faces and quality" json canon.json "j['same_vertex_count'] and j['faces'] > 4000 and j['has_quality']"
check "canonical form differs from the input pose" json canon.json "j['aligned_rms'] > 0.01"
"$cf" canonical fig.ply canonA.ply --variant A --alpha 8 --beta 12 --seed 5 --tol 1e-4 --max-iter 50 --json > canonA.json
check "canonical variant A with every option" json canonA.json "j['variant'] == 'A' and j['beta'] == 12 and j['alpha'] == 8 and j['iterations'] <= 50 and j['random'] > 0"

"$cf" simplify fig.ply simple.ply --vertices 1000 2>/dev/null
"$plycheck" simple.ply > simple.json
check "simplify to ~1000 vertices (closed mesh kept closed)" json simple.json "900 <= j['vertices'] <= 1100 and abs(j['faces'] - (2 * j['vertices'] - 4)) <= 2"
check "canonical form of the simplified mesh" "$cf" canonical simple.ply simple_canon.ply --quiet

"$cf" simplify fig.ply fig600.ply --vertices 600 2>/dev/null
for m in geodesic-ls geodesic-classical geodesic-fast; do
  "$cf" canonical fig600.ply geo_$m.ply --method $m --json > geo_$m.json
  check "canonical --method $m" json geo_$m.json "j['method'] == '$m' and j['geodesic_seconds'] > 0 and j['vertices'] < 700"
done
"$cf" canonical fig.ply refused.ply --method geodesic-ls --max-memory-gib 0.001 > err.txt 2>&1
check "geodesic method refused over --max-memory-gib, naming memory and time" \
  bash -c "[ $? -eq 1 ] && grep -q 'needs about .* GiB and .* s' err.txt && [ ! -e refused.ply ]"

"$cf" picture pic.png cf.ply --points fp.ply --canonical canon.ply --size 200 2>/dev/null
check "picture is a PNG" bash -c "head -c 8 pic.png | od -An -c | grep -q 'P   N   G'"

# --- view descriptors: views, codebook, descriptor, distance ----------------------------------
"$cf" views fig.ply views 2>/dev/null
check "views: 66 PNGs and a contact sheet" bash -c "[ \$(ls views/view_*.png | wc -l) -eq 66 ] && [ -s views/contact_sheet.png ]"
"$cf" generate fig_b.ply --vertices 3000 --pose 5
"$cf" codebook cb.bin fig.ply fig_b.ply --words 100 2>codebook.log
check "codebook written" test -s cb.bin
check "progress in a log: no carriage return, a short run writes only its result" \
  bash -c "! grep -q \$'\\r' codebook.log && [ \$(grep -c 'meshes, ' codebook.log) -eq 0 ] && grep -q '^codebook of 100 words' codebook.log"
CANONFORM_PROGRESS_INTERVAL=0 "$cf" codebook cb2.bin fig.ply fig_b.ply --words 100 2>codebook2.log
check "progress in a log: one whole line per update (CANONFORM_PROGRESS_INTERVAL=0)" \
  bash -c "grep -qx '1/2 meshes, [0-9]* SIFT descriptors' codebook2.log && grep -qx '2/2 meshes, [0-9]* SIFT descriptors' codebook2.log"
for m in fig fig_b canon; do "$cf" descriptor $m.ply $m.cfvd --codebook cb.bin --json > $m.desc.json; done
check "descriptor --json: 66 views over a 100-word codebook" json fig.desc.json "j['views'] == 66 and j['codebook_words'] == 100 and j['keypoints'] > 100"
"$cf" descriptor fig.ply fig_raw.cfvd
check "descriptor without a codebook (raw SIFT)" test -s fig_raw.cfvd
"$cf" distance dist.bin fig.cfvd fig_b.cfvd canon.cfvd 2>/dev/null
check "distance: 3 x 3 float32 matrix and CSV" bash -c "[ \$(stat -c %s dist.bin) -eq 36 ] && [ \$(wc -l < dist.bin.csv) -eq 3 ]"
check "distance: symmetric, zero diagonal, positive off-diagonal" /usr/bin/python3 -c "
import csv; D = [[float(x) for x in r] for r in csv.reader(open('dist.bin.csv'))]
assert all(D[i][i] == 0 for i in range(3)) and all(D[i][j] == D[j][i] > 0 for i in range(3) for j in range(3) if i != j)"
printf 'path,class\nfig.ply,a\nfig_b.ply,a\ncanon.ply,a\n' > labels.csv
"$cf" evaluate dist.bin --labels labels.csv --json --pr pr.csv > eval.json
check "evaluate: measures in [0, 1] and 20 precision values" json eval.json "0 <= j['micro']['nn'] <= 1 and len(j['precision']) == 20"
check "evaluate: precision-recall CSV of 20 points" bash -c "[ \$(wc -l < pr.csv) -eq 21 ]"
# --- retrieve: a small labelled collection, the cache ----------------------------------------
mkdir -p coll
for p in 0 1 2; do "$cf" generate coll/a$p.ply --vertices 1200 --pose $p; done
for p in 3 4 5; do "$cf" generate coll/b$p.ply --vertices 600 --pose $p; done
printf 'path,class\na0.ply,a\na1.ply,a\na2.ply,a\nb3.ply,b\nb4.ply,b\nb5.ply,b\n' > coll/labels.csv
mkdir -p coll/corres  # the poses of one figure share their vertices: identity correspondences
for p in 0 1 2; do seq 1 1200 > coll/corres/a$p.vts; done
for p in 3 4 5; do seq 1 600 > coll/corres/b$p.vts; done
"$cf" retrieve --dataset coll --out run --method none,euclidean-N --words 50 > run1.out 2> run1.err
check "retrieve: report, metrics and matrices for both methods" bash -c "[ -s run/report.md ] && [ -s run/none/metrics.json ] && [ \$(stat -c %s run/euclidean-N/distances.bin) -eq 144 ]"
check "retrieve: precision-recall plot of both methods in the report" bash -c "[ -s run/pr.png ] && grep -q 'pr.png' run/report.md"
check "retrieve: pose consistency measured, lower for the canonical forms" /usr/bin/python3 -c "
import json; a = json.load(open('run/none/metrics.json')); b = json.load(open('run/euclidean-N/metrics.json'))
assert a['pose_consistency_pairs'] == 6 and 0 < b['pose_consistency'] < a['pose_consistency'], (a, b)"
check "retrieve: first run computes everything" grep -q "6 meshes in .* s (0 from the cache, 0 failed)" run1.err
cp run/euclidean-N/forms/a0.ply run_n_a0.ply
"$cf" retrieve --dataset coll --out run --method euclidean-N --words 50 > run2.out 2> run2.err
check "retrieve: a re-run recomputes nothing" grep -q "(6 from the cache, 0 failed)" run2.err
"$cf" retrieve --dataset coll --out run --method euclidean-N --words 50 --noise 0.1 > run3.out 2> run3.err
check "retrieve: a changed parameter (--noise) recomputes" grep -q "(0 from the cache, 0 failed)" run3.err
check "retrieve: the forms of the changed parameter replace the others" bash -c "! cmp -s run/euclidean-N/forms/a0.ply run_n_a0.ply"
"$cf" retrieve --dataset coll --out run --method euclidean-N --words 50 > run3b.out 2> run3b.err
check "retrieve: back to the first parameters, the cached forms are restored" bash -c "grep -q '(6 from the cache, 0 failed)' run3b.err && cmp -s run/euclidean-N/forms/a0.ply run_n_a0.ply"
# --seed seeds the codebook (and the noise), not the forms and views: another seed takes them from the cache
cp -r run run_seed
"$cf" retrieve --dataset coll --out run_seed --method none,euclidean-N --words 50 --seed 1 > run4.out 2> run4.err
check "retrieve: another --seed takes every form and view from the cache" bash -c "[ \$(grep -c '(6 from the cache, 0 failed)' run4.err) -eq 2 ]"
check "retrieve: another --seed trains other codebooks" bash -c "[ \$(ls run_seed/cache/codebook_*.bin | wc -l) -gt \$(ls run/cache/codebook_*.bin | wc -l) ]"
/usr/bin/python3 "$experiments/paired_nn.py" run/none run/euclidean-N run_seed/none run_seed/euclidean-N > paired.out 2>&1
check "paired_nn.py: per-pair NN equals the runs' metrics, and a summary over the pairs" /usr/bin/python3 -c "
import json, re
out = open('paired.out').read()
nn = [float(x) for x in re.findall(r'NN ([0-9.]+) vs ([0-9.]+)', out)[0]]
assert nn == [round(json.load(open('run/%s/metrics.json' % m))['micro']['nn'], 3) for m in ('none', 'euclidean-N')], (out, nn)
assert 'over 2 pairs: right in a majority of pairs' in out, out"
# fused_rules.py: its row z-score rule at weight 0.7 and global median at 0.8 are the tool's fused: and
# fused-median: methods at their default weights (the tool's methods run in a copy, all from the cache)
cp -r run run_fused
"$cf" retrieve --dataset coll --out run_fused --method none,euclidean-N,fused:none+euclidean-N,fused-median:none+euclidean-N --words 50 > run_fused.out 2> run_fused.err
/usr/bin/python3 "$experiments/fused_rules.py" "$cf" run --rules row-z,global-median --weights 0.7 0.8 --csv rules.csv > rules.out 2>&1
check "fused_rules.py: row z-score at 0.7 and global median at 0.8 score as fused: and fused-median:" /usr/bin/python3 -c "
import csv, json
rows = {(r['rule'], r['w_euclidean-N']): r for r in csv.DictReader(open('rules.csv'))}
for rule, w, method in (('row-z', '0.700', 'fused_none+euclidean-N'), ('global-median', '0.800', 'fused-median_none+euclidean-N')):
    j = json.load(open('run_fused/%s/metrics.json' % method))['micro']
    for k in ('nn', 'first_tier', 'second_tier', 'e_measure', 'dcg'):
        assert abs(float(rows[rule, w][k]) - j[k]) < 1e-5, (rule, k, rows[rule, w], j)
out = open('rules.out').read()
assert '| row z-score (\`fused:\`) |' in out and '| global median (\`fused-median:\`) |' in out, out"
# beta: part of the cache key (the variant's default, 130, is the same computation as no beta)
"$cf" retrieve --dataset coll --out run --method euclidean-N:beta=130 --words 50 > run5.out 2> run5.err
check "retrieve: euclidean-N:beta=130 is the default beta (all from the cache)" grep -q "\[euclidean-N_beta130\] 6 meshes in .* (6 from the cache, 0 failed)" run5.err
"$cf" retrieve --dataset coll --out run --method euclidean-N:beta=40,euclidean-A:beta=5 --words 50 > run6.out 2> run6.err
check "retrieve: a changed beta recomputes" bash -c "grep -q '\[euclidean-N_beta40\] 6 meshes in .* (0 from the cache, 0 failed)' run6.err && grep -q '\[euclidean-A_beta5\] 6 meshes in .* (0 from the cache, 0 failed)' run6.err"
check "retrieve: the beta is in metrics.json" json run/euclidean-N_beta40/metrics.json "j['beta'] == 40 and j['base'] == 'euclidean-N'"
check "retrieve: the default beta is in metrics.json" json run/euclidean-N/metrics.json "j['beta'] == 130"
check "retrieve: another beta gives other forms" bash -c "! cmp -s run/euclidean-N/forms/a0.ply run/euclidean-N_beta40/forms/a0.ply"
"$cf" retrieve --dataset coll --out run_x --method euclidean-N:beta=x > err.txt 2>&1
check "retrieve: a bad beta fails with a reason" bash -c "[ $? -eq 1 ] && grep -q 'beta must be a positive number' err.txt"
"$cf" retrieve --dataset coll --out run_x --method geodesic-ls:beta=5 > err.txt 2>&1
check "retrieve: beta on a geodesic method fails with a reason" bash -c "[ $? -eq 1 ] && grep -q 'only euclidean-A and euclidean-N take' err.txt"
# grid: originals beside canonical forms (Figs. 8/9)
check "retrieve: grid.png written and linked from the report" bash -c "head -c 8 run/grid.png | od -An -c | grep -q 'P   N   G' && grep -q '(grid.png)' run/report.md"
"$cf" grid g8.png run --methods euclidean-N > g8.out 2>&1
"$cf" grid g8b.png run --methods euclidean-N,euclidean-N_beta40,euclidean-A_beta5 > g8b.out 2>&1
check "grid: one column per class, one row more per method" /usr/bin/python3 -c "
import struct
size = lambda p: struct.unpack('>II', open(p, 'rb').read(24)[16:24])
(w1, h1), (w2, h2) = size('g8.png'), size('g8b.png')
assert 'grid: 2 models' in open('g8.out').read()
assert w1 == w2 and h2 > h1 and (h2 - h1) % 2 == 0, (w1, h1, w2, h2)"
"$cf" grid g9.png run --class a --methods euclidean-N > g9.out 2>&1
check "grid --class: the models of one class (Fig. 9)" grep -q 'grid: 3 models' g9.out
"$cf" grid gx.png coll > err.txt 2>&1
check "grid of a folder that is no run fails with a reason" bash -c "[ $? -eq 1 ] && grep -q 'no collection.csv' err.txt && [ ! -e gx.png ]"
"$cf" grid gx.png run --methods geodesic-ls > err.txt 2>&1
check "grid of a method the run lacks fails with a reason" bash -c "[ $? -eq 1 ] && grep -q \"no method 'geodesic-ls'\" err.txt"
# precision-recall curves (Figs. 10, 11): drawn by the tool, in retrieve's report and by `canonform pr`
"$cf" pr prs.png run=A run_seed=B --title "two runs" > pr.out 2>&1
check "pr: the curves of every method of both runs on one plot" bash -c "grep -q 'pr: [0-9]* curves -> prs.png' pr.out && head -c 8 prs.png | od -An -c | grep -q 'P   N   G'"
check "pr: one curve per method folder with a pr.csv, labelled by its run" bash -c "[ \$(grep -o 'pr: [0-9]*' pr.out | cut -d' ' -f2) -eq \$(ls run/*/pr.csv run_seed/*/pr.csv | wc -l) ]"
"$cf" pr prx.png coll > err.txt 2>&1
check "pr of a folder that is no run fails with a reason" bash -c "[ $? -eq 1 ] && grep -q 'has no METHOD/pr.csv' err.txt && [ ! -e prx.png ]"
printf 'recall,precision\n0.05,1.5\n' > run_seed/none/pr.csv
"$cf" pr prx.png run_seed > err.txt 2>&1
check "pr of a malformed pr.csv fails naming the file and line" bash -c "[ $? -eq 1 ] && grep -q 'none/pr.csv: line 2' err.txt && [ ! -e prx.png ]"
# a procedural labelled collection
"$cf" generate --collection pcoll --vertices 800 --poses 3 --classes standard,long-arms,stocky > gen.out 2>&1
check "generate --collection: classes x poses meshes, labels and correspondences" bash -c "[ \$(tail -n +2 pcoll/labels.csv | wc -l) -eq 9 ] && [ \$(grep -c ',stocky\$' pcoll/labels.csv) -eq 3 ] && [ \$(ls pcoll/meshes/*.ply | wc -l) -eq 9 ] && [ \$(wc -l < pcoll/corres/stocky_2.vts) -eq 800 ]"
"$plycheck" pcoll/meshes/long-arms_1.ply > la.json
check "generate --collection: the figures have the requested vertices" json la.json "j['vertices'] == 800"
check "generate --collection: classes differ in shape" bash -c "! cmp -s pcoll/meshes/standard_0.ply pcoll/meshes/long-arms_0.ply"
"$cf" generate x.ply --class giraffe > err.txt 2>&1
check "generate --class: an unknown class is a usage error naming the known ones" bash -c "[ $? -eq 2 ] && grep -q 'known: standard' err.txt && [ ! -e x.ply ]"
"$cf" retrieve --dataset coll --out run_s --method none,euclidean-N --words 50 --simplify 500 --threads 2 > run7.out 2> run7.err
check "retrieve --simplify on two threads (one simplification at a time)" bash -c "[ $? -eq 0 ] && grep -q '| euclidean-N | .* | 6 | 0 |' run_s/report.md"
check "retrieve --simplify: the forms are simplified (1200 -> about 500 vertices)" bash -c "[ \$(grep -a -m1 'element vertex' run_s/euclidean-N/forms/a0.ply | cut -d' ' -f3) -le 550 ]"
check "retrieve --simplify: no pose consistency (correspondences name original vertices)" json run_s/euclidean-N/metrics.json "j['pose_consistency'] == -1"
printf 'garbage' > coll/bad.off; printf 'bad.off,a\n' >> coll/labels.csv
"$cf" retrieve --dataset coll --out run_bad --method none --words 50 > run4.out 2> run4.err
check "retrieve: a failing mesh is named with its reason and left out" bash -c "grep -q 'bad: cannot read' run_bad/none/failures.txt && grep -q '| none | .* | 6 | 1 |' run_bad/report.md"

"$cf" distance bad.bin fig_raw.cfvd fig.cfvd > err.txt 2>&1
check "distance refuses raw descriptors with a reason" bash -c "[ $? -eq 1 ] && grep -q 'raw SIFT' err.txt && [ ! -e bad.bin ]"
printf 'not a codebook' > badcb.bin
"$cf" descriptor fig.ply x.cfvd --codebook badcb.bin > err.txt 2>&1
check "descriptor with a broken codebook fails with a reason" bash -c "[ $? -eq 1 ] && [ ! -e x.cfvd ] && [ -s err.txt ]"
"$cf" descriptor fp.ply x.cfvd > err.txt 2>&1
check "descriptor of a point cloud fails with a reason" bash -c "[ $? -eq 1 ] && grep -q 'point cloud' err.txt && [ ! -e x.cfvd ]"

# --- bad input: exit 1, message naming the problem, no output left ---------------------------
expect_error() {  # DESCRIPTION PATTERN FILE
  local out="out_$RANDOM.ply"
  "$cf" canonical "$3" "$out" > err.txt 2>&1
  local rc=$?
  if [ $rc -eq 1 ] && grep -qi -- "$2" err.txt && [ ! -e "$out" ] && ! ls .out_* >/dev/null 2>&1; then
    pass "$1 -> $(head -c 160 err.txt | tr '\n' ' ')"
  else
    fail "$1 (exit $rc, output: $(cat err.txt))"
  fi
}
expect_error "missing file" "no such file" nothing.ply
: > empty.off
expect_error "empty file" "empty" empty.off
printf 'this is not a mesh\n' > garbage.off
expect_error "unreadable file" "cannot read" garbage.off
expect_error "point cloud" "point cloud" fp.ply
printf 'OFF\n4 2 0\n0 0 0\n1 0 0\n0 1 0\n1 1 nan\n3 0 1 2\n3 1 3 2\n' > nan.off
expect_error "NaN coordinates" "NaN" nan.off
printf 'OFF\n4 2 0\n0 0 0\n1 0 0\n0 1 0\n1 1 0\n3 0 1 2\n3 1 3 2\n' > tiny.off
expect_error "fewer than 10 vertices" "only 4 vertices" tiny.off
{ echo OFF; echo "12 12 0"  # three separate tetrahedra
  for o in 0 3 6; do echo "$o 0 0"; echo "$((o + 1)) 0 0"; echo "$o 1 0"; echo "$o 0 1"; done
  for b in 0 4 8; do echo "3 $b $((b + 2)) $((b + 1))"; echo "3 $b $((b + 1)) $((b + 3))"
                     echo "3 $b $((b + 3)) $((b + 2))"; echo "3 $((b + 1)) $((b + 2)) $((b + 3))"; done; } > comps.off
expect_error "several components" "3 connected components" comps.off
{ echo OFF; echo "12 3 0"; for k in 0 1 2 3 4 5 6 7 8 9 10 11; do echo "$k $((k * k % 7)) $((k % 4))"; done
  echo "3 0 1 2"; echo "3 0 1 3"; echo "3 0 1 4"; } > nonmanifold.off
expect_error "non-manifold edge" "non-manifold" nonmanifold.off
{ echo OFF; echo "12 2 0"; for k in 0 1 2 3 4 5 6 7 8 9 10 11; do echo "$k 0 0"; done
  echo "3 0 1 2"; echo "3 3 4 5"; } > degenerate.off
expect_error "degenerate faces" "degenerate" degenerate.off
"$cf" canonical fig.ply x.ply --variant Q > err.txt 2>&1
check "usage error exits 2" test $? -eq 2
finish
