#!/usr/bin/env bash
# Linear static benchmark (make bench): a block of N^3 cells x 5 tets, bottom face fixed, top
# face pushed down by a prescribed displacement, once with ME-FEM tets (ELFORM 43) and once
# with standard linear tets (ELFORM 10) on the same mesh. Prints the unknowns, assembly and
# MUMPS times, factor memory and peak memory of each run, on 1 and 2 ranks.
# BENCH_LS_CELLS (default 26: 87 880 tets, 329 k unknowns with ME-FEM) sets N.
set -euo pipefail
cd "$(dirname "$0")/../.."
export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1
export OMPI_MCA_rmaps_base_oversubscribe=1 OPENBLAS_NUM_THREADS=1
n=${BENCH_LS_CELLS:-26}
out=tests/out/bench_linear_static
mkdir -p "$out"
mesh=$out/block_$n.mesh.k
[ -f "$mesh" ] || /usr/bin/python3 tests/bench/generate_block_deck.py $n $n $n "$mesh" --tets 5 >/dev/null
per_layer=$(( (n + 1) * (n + 1) ))
first_top=$(( n * per_layer + 1 ))
last_top=$(( (n + 1) * per_layer ))
for elform in 43 10; do
  deck=$out/block_${n}_elform$elform.k
  {
    sed -e '/^\*END/d' -e "s/^         1        43/         1        $elform/" "$mesh"
    cat <<K
*SET_NODE_LIST_GENERATE
         1
         1$(printf '%10d' $per_layer)
*SET_NODE_LIST_GENERATE
         2
$(printf '%10d%10d' $first_top $last_top)
*BOUNDARY_SPC_SET
         1         0         1         1         1
*BOUNDARY_PRESCRIBED_MOTION_SET
         2         3         2         1     -0.01
*DEFINE_CURVE
         1
                 0.0                 1.0
                 1.0                 1.0
*CONTROL_TERMINATION
       1.0
*CONTROL_IMPLICIT_GENERAL
         1       1.0
*CONTROL_IMPLICIT_SOLUTION
         1
*END
K
  } > "$deck"
  grep -q "^         1        $elform" "$deck" || { echo "could not set ELFORM $elform"; exit 1; }
  for np in 1 2; do
    echo "== linear static, ELFORM $elform, $np rank(s), block $n^3 x 5 tets"
    mpirun --oversubscribe -np $np bin/mefem -o "$out/run_${elform}_np$np" "$deck" 2>&1 \
      | grep -E 'model:|enrichment|equations|MUMPS|wall time' | sed 's/^/  /'
  done
done
