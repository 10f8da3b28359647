#!/usr/bin/env bash
# Nonlinear implicit benchmark (make bench): a block of N^3 cells x 5 ME-FEM tets of
# elasto-plastic aluminium (*MAT_POWER_LAW_PLASTICITY), bottom fixed, top pushed down by 0.6 %
# in 3 steps with full Newton (yield at 0.14 %: the block yields from the first step on; with
# 1 % per step the first step's top layer, which takes the whole prescribed increment before
# the first solve, inverted elements on 23^3 cells and the step was cut back twice). Prints Newton iterations per step, time per iteration split into
# assembly (material update + forces + tangent) and MUMPS phases, and memory, on 1 and 2 ranks.
# BENCH_PL_CELLS (default 24: 69 120 tets, about 254 000 unknowns) sets N; BENCH_PL_RANKS the
# rank counts (default "1 2").
set -euo pipefail
cd "$(dirname "$0")/../.."
export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1
export OMPI_MCA_rmaps_base_oversubscribe=1 OPENBLAS_NUM_THREADS=1
n=${BENCH_PL_CELLS:-24}
out=tests/out/bench_plasticity
mkdir -p "$out"
mesh=$out/block_$n.mesh.k
[ -f "$mesh" ] || /usr/bin/python3 tests/bench/generate_block_deck.py $n $n $n "$mesh" --tets 5 >/dev/null
per_layer=$(( (n + 1) * (n + 1) ))
deck=$out/block_${n}_plastic.k
{
  # aluminium, power-law hardening (mm, tonne, s, N, MPa)
  sed -e '/^\*END/d' -e '/^\*MAT_ELASTIC/,/^\*/{/^\*MAT_ELASTIC/d;/^[^*]/d}' "$mesh"
  shift_z=$(awk "BEGIN { printf \"%10.4f\", -0.006 * $n }")
  cat <<K
*MAT_POWER_LAW_PLASTICITY
         1    2.7e-9   70000.0       0.3     500.0      0.25
     100.0
*SET_NODE_LIST_GENERATE
         1
         1$(printf '%10d' $per_layer)
*SET_NODE_LIST_GENERATE
         2
$(printf '%10d%10d' $(( n * per_layer + 1 )) $(( (n + 1) * per_layer )))
*BOUNDARY_SPC_SET
         1         0         1         1         1
*BOUNDARY_PRESCRIBED_MOTION_SET
         2         3         2         1$shift_z
*DEFINE_CURVE
         1
                 0.0                 0.0
                 1.0                 1.0
*CONTROL_TERMINATION
       1.0
*CONTROL_IMPLICIT_GENERAL
         1  0.333334
*CONTROL_IMPLICIT_SOLUTION
        12
*DATABASE_BINARY_D3PLOT
       1.0
*END
K
} > "$deck"
for np in ${BENCH_PL_RANKS:-1 2}; do
  echo "== nonlinear implicit (J2 plasticity), ME-FEM tets, $np rank(s), block $n^3 x 5 tets"
  mpirun --oversubscribe -np $np bin/mefem -o "$out/run_np$np" "$deck" 2>&1 \
    | grep --line-buffered -E '^model:|enrichment|^implicit|^step|wall time' | sed -u 's/^/  /'
done
