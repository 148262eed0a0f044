#!/usr/bin/env bash
# SPDX-License-Identifier: GPL-3.0-or-later
# A retrieval experiment with the canonform tool (a shell precursor of `canonform retrieve`):
# canonical forms of every mesh of a labelled collection, a codebook trained on them, one
# descriptor per mesh, the clock-matching distance matrix and the psbTable measures.
#   tools/retrieval_experiment.sh COLLECTION_DIR OUT_DIR METHOD [WORDS]
# COLLECTION_DIR holds labels.csv ("path,class", paths relative to it); METHOD is none,
# euclidean-A, euclidean-N, geodesic-ls, geodesic-classical or geodesic-fast. Uses both cores.
set -euo pipefail
[ $# -ge 3 ] || { sed -n '5,7p' "$0"; exit 2; }
coll=$(realpath "$1"); out=$2; method=$3; words=${4:-1500}
cf=${CANONFORM:-$(dirname "$0")/../build/apps/canonform}
cf=$(realpath "$cf")
mkdir -p "$out/forms" "$out/descriptors"
out=$(realpath "$out")
start=$(date +%s.%N)
tail -n +2 "$coll/labels.csv" | cut -d, -f1 > "$out/paths.txt"
n=$(wc -l < "$out/paths.txt")
form() {  # PATH: the canonical form of one mesh (or the mesh itself for 'none')
  local name; name=$(basename "${1%.*}")
  case "$method" in
    none) cp "$coll/$1" "$out/forms/$name.${1##*.}" ;;
    euclidean-A) "$cf" canonical "$coll/$1" "$out/forms/$name.ply" --variant A --quiet ;;
    euclidean-N) "$cf" canonical "$coll/$1" "$out/forms/$name.ply" --variant N --quiet ;;
    geodesic-*) "$cf" canonical "$coll/$1" "$out/forms/$name.ply" --method "$method" --threads 1 --quiet ;;
    *) echo "unknown method $method" >&2; exit 2 ;;
  esac
}
export -f form; export cf coll out method
xargs -P 2 -I{} bash -c 'form "$@"' _ {} < "$out/paths.txt"
t_forms=$(date +%s.%N)
ls "$out"/forms/* > "$out/forms.txt"
"$cf" codebook "$out/codebook.bin" $(cat "$out/forms.txt") --words "$words" 2> "$out/codebook.log"
t_codebook=$(date +%s.%N)
export words
while read -r p; do echo "$(basename "${p%.*}")"; done < "$out/paths.txt" > "$out/names.txt"
xargs -P 2 -I{} sh -c 'f=$(ls "$0"/forms/{}.* | head -n 1); "$1" descriptor "$f" "$0/descriptors/{}.cfvd" --codebook "$0/codebook.bin"' "$out" "$cf" < "$out/names.txt"
t_desc=$(date +%s.%N)
"$cf" distance "$out/distances.bin" $(sed "s|^|$out/descriptors/|; s|$|.cfvd|" "$out/names.txt") 2> "$out/distance.log"
"$cf" evaluate "$out/distances.bin" --labels "$coll/labels.csv" --pr "$out/pr.csv" > "$out/measures.md"
"$cf" evaluate "$out/distances.bin" --labels "$coll/labels.csv" --json > "$out/measures.json"
end=$(date +%s.%N)
printf '%s: %d meshes, forms %.1f s, codebook %.1f s, descriptors %.1f s, distances+measures %.1f s, total %.1f s\n' \
  "$method" "$n" "$(echo "$t_forms - $start" | bc)" "$(echo "$t_codebook - $t_forms" | bc)" \
  "$(echo "$t_desc - $t_codebook" | bc)" "$(echo "$end - $t_desc" | bc)" "$(echo "$end - $start" | bc)" | tee "$out/timing.txt"
head -4 "$out/measures.md"
