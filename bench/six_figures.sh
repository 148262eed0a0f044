# Sourced by the bench scripts: six_figures BUILD_DIR DIR writes six procedural figures of 10k
# vertices into DIR (the six body types, poses 1-6), the collection of the 600-mesh plan and the
# query benchmark.
six_figures() {
  local build=$1 dir=$2 pose=1 c
  for c in standard long-arms short-legs long-tail stocky long-neck; do
    "$build/tools/canonform" generate "$dir/$c.ply" --vertices 10000 --pose $pose --class $c
    pose=$((pose + 1))
  done
}
