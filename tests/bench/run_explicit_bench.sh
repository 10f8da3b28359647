#!/usr/bin/env bash
# Explicit-dynamics benchmark (make bench; doc/performance.md "Explicit dynamics"): a block of
# NX x NY x NZ cubes (x 5 tets, or as hexahedra) of elasto-plastic aluminium (*MAT_PIECEWISE_LINEAR_PLASTICITY with
# an EPS/ES table), bottom face fixed, top face driven down at a constant speed (plastic wave
# from the first cycles), ENDCYC cycles, one result state (at the end). The same deck is run
# with ME-FEM tets (ELFORM 43), nodal-pressure tets (13), standard tets (10) and, with the cubes
# as hexahedra (the same nodes), one-point hexahedra (1, hourglass control IHQ 6, QM 1) on
# 1 and 2 ranks; the table gives ns per element-cycle and per cell-cycle (core time = loop wall time x ranks, as the
# driver's summary line "explicit: ... ns per element-cycle" says), the driver's phase shares of
# rank 0, peak memory, the speed-up from 1 to 2 ranks and the spread of the force time over
# the ranks (driver's line "explicit: min / max over ranks: ...").
#
# Every case runs BENCH_EX_REPEAT times (default 3), the repetitions interleaved (all cases
# once, then all again), because single runs on this VM vary by 10-30 % (the 2-rank ones
# most): each row shows the run with the median ns per element-cycle and all runs' figures,
# and the speed-up is given per repetition (1 and 2 ranks of the same round) as median and
# range.
#
# usage: tests/bench/run_explicit_bench.sh [--small]
#   default: 34 x 34 x 35 cubes = 202 300 tets, 300 cycles (about 4 minutes on 2 cores)
#   --small: 12 x 12 x 12 cubes = 8 640 tets, 100 cycles (a few seconds)
# Environment: BENCH_EX_CELLS="NX NY NZ", BENCH_EX_CYCLES, BENCH_EX_RANKS (default "1 2"),
# BENCH_EX_ELFORMS (default "43 13 10 1"), BENCH_EX_IHQ and BENCH_EX_QH (the hexahedra's
# *CONTROL_HOURGLASS, default 6 and 1.0: the stiffness form, the dearer one), BENCH_EX_SPEED (top speed, mm/s; default 20000),
# BENCH_EX_REPEAT (default 3), BENCH_EX_PAIR (default 1: after each 2-rank run, two independent
# 1-rank runs at the same time, see below; 0: not), MEFEM (binary, default bin/mefem).
#
# The pair of 1-rank runs measures what this machine gives two processes at once (shared
# caches, memory, the host's other load): their ns per element-cycle over the 1-rank run's
# bounds the speed-up any 2-rank run can reach here ("machine bound"), and their ns over the
# 2-rank run's is the 2-rank run's efficiency against that bound (what MPI, the halo and the
# ranks waiting for each other cost).
set -euo pipefail
cd "$(dirname "$0")/../.."
export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1
export OMPI_MCA_rmaps_base_oversubscribe=1 OPENBLAS_NUM_THREADS=1

cells="34 34 35"
cycles=300
if [ "${1:-}" = "--small" ]; then
  cells="12 12 12"
  cycles=100
elif [ -n "${1:-}" ]; then
  echo "usage: $0 [--small]" >&2
  exit 2
fi
cells=${BENCH_EX_CELLS:-$cells}
cycles=${BENCH_EX_CYCLES:-$cycles}
ranks=${BENCH_EX_RANKS:-1 2}
elforms=${BENCH_EX_ELFORMS:-43 13 10 1}
ihq=${BENCH_EX_IHQ:-6}
qh=${BENCH_EX_QH:-1.0}
speed=${BENCH_EX_SPEED:-20000.0}
repeat=${BENCH_EX_REPEAT:-3}
pair=${BENCH_EX_PAIR:-1}
mefem=${MEFEM:-bin/mefem}
read -r nx ny nz <<< "$cells"

out=tests/out/bench_explicit
mkdir -p "$out"
tag=${nx}x${ny}x${nz}
mesh=$out/block_$tag.mesh.k
[ -f "$mesh" ] || /usr/bin/python3 tests/bench/generate_block_deck.py $nx $ny $nz "$mesh" \
  --tets 5 >/dev/null
hex_mesh=$out/block_${tag}_hex.mesh.k
case " $elforms " in
  *" 1 "*) [ -f "$hex_mesh" ] || /usr/bin/python3 tests/bench/generate_block_deck.py \
             $nx $ny $nz "$hex_mesh" --tets 1 >/dev/null ;;
esac
per_layer=$(( (nx + 1) * (ny + 1) ))
top_first=$(( nz * per_layer + 1 ))
top_last=$(( (nz + 1) * per_layer ))

# deck of one element formulation: mesh without its *MAT_ELASTIC, then the plastic material,
# the sets, conditions and controls (mm, tonne, s, N, MPa)
write_deck() {
  local elform=$1 deck=$2 source=$mesh
  [ "$elform" = 1 ] && source=$hex_mesh
  {
    sed -e '/^\*END/d' -e '/^\*MAT_ELASTIC/,/^\*/{/^\*MAT_ELASTIC/d;/^[^*]/d}' \
        -e "s/^         1        43\$/$(printf '%10d%10d' 1 "$elform")/" "$source"
    cat <<K
*MAT_PIECEWISE_LINEAR_PLASTICITY
\$#     mid        ro         e        pr      sigy      etan
         1    2.7e-9   70000.0      0.33     100.0
\$#       c         p      lcss      lcsr        vp
                                                  
\$#    eps1      eps2      eps3      eps4      eps5
       0.0      0.02      0.05       0.1       1.0
\$#     es1       es2       es3       es4       es5
     100.0     130.0     150.0     165.0     250.0
*SET_NODE_LIST_GENERATE
         1
$(printf '%10d%10d' 1 $per_layer)
*SET_NODE_LIST_GENERATE
         2
$(printf '%10d%10d' $top_first $top_last)
*BOUNDARY_SPC_SET
         1         0         1         1         1
*BOUNDARY_PRESCRIBED_MOTION_SET
         2         3         0         1$(printf '%10.1f' "-$speed")
*DEFINE_CURVE
         1
                 0.0                 1.0
                 1.0                 1.0
$( [ "$elform" = 1 ] && printf '*CONTROL_HOURGLASS\n%10d%10.1f\n' "$ihq" "$qh" )
*CONTROL_TERMINATION
       1.0$(printf '%10d' $cycles)
*CONTROL_TIMESTEP
                 0.9
*DATABASE_BINARY_D3PLOT
       1.0
*END
K
  } > "$deck"
}

# one run: prints the summary numbers as "key=value" words (optional 5th argument: the
# result directory's suffix, for runs made at the same time; 6th: binding, default Open MPI's)
run_case() {
  local elform=$1 np=$2 deck=$3 log=$4 suffix=${5:-} bind=${6:-}
  head -1 /proc/stat > "$log.stat"
  /usr/bin/time -f 'process %e %U %S' -o "$log.time" \
    mpirun --oversubscribe ${bind:+--bind-to $bind} -np "$np" "$mefem" \
    -o "$out/run_${elform}_np$np$suffix" "$deck" > "$log" 2>&1 \
    || { echo "mefem failed, see $log" >&2; tail -5 "$log" >&2; exit 1; }
  head -1 /proc/stat >> "$log.stat"
  /usr/bin/python3 - "$log" "$np" <<'PY'
import re, sys
log, np_ = sys.argv[1], int(sys.argv[2])
text = open(log).read()
wall, user, system = (float(v) for v in open(log + '.time').read().split()[1:4])
def grab(pattern, cast=float, default=float('nan')):
    m = re.search(pattern, text)
    return cast(m.group(1)) if m else default
g = {}
g['elements'] = grab(r'model: \S+ nodes?, (\d+) elements', int, 0) or \
    grab(r'(\d+) elements', int, 0)
g['cells'] = grab(r'explicit: \d+ nodes \(with enriched\), (\d+) cells', int, 0)
g['cycles'] = grab(r'explicit: (\d+) cycles, ', int, 0)
g['analysis'] = grab(r'explicit: \d+ cycles, (\S+) s')
g['ns_elem'] = grab(r'explicit: (\S+) ns per element-cycle')
g['ns_cell'] = grab(r'ns per element-cycle, (\S+) ns per cell-cycle')
g['forces'] = grab(r'time in forces (\S+) %')
g['halo'] = grab(r'halo exchange and reductions (\S+) %')
g['update'] = grab(r'nodal update (\S+) %')
g['output'] = grab(r'output (\S+) %')
g['mem_max'] = grab(r'(\S+) MiB max over ranks')
# the median cycle's wall time (the driver's 50 % percentile of the wall time per cycle)
g['cycle_p50'] = grab(r'% of cycles below\s+\S+ /\s*(\S+) /')
# several ranks: the spread of the force time over ranks (load imbalance) and the halo wait
g['forces_min'] = grab(r'min / max over ranks: .* forces (\S+) /')
g['forces_max'] = grab(r'min / max over ranks: .* forces \S+ / (\S+) s')
g['wait_max'] = grab(r'halo wait \S+ / (\S+) s')
# share of the ranks' time they were on a core (user + system of mpirun and the ranks over
# wall x ranks): well below 1 means other processes competed for the cores
g['cpu_share'] = (user + system) / (wall * np_)
# share of the machine's CPU time the host took from this VM during the run ("steal" of the
# cpu line of /proc/stat, over all its columns): the host running other guests on our cores
before, after = ([int(v) for v in line.split()[1:]] for line in open(log + '.stat'))
ticks = [b - a for a, b in zip(before, after)]
g['host_steal'] = ticks[7] / max(sum(ticks[:8]), 1)
print(' '.join(f'{k}={v}' for k, v in g.items()))
PY
}

printf '== explicit dynamics benchmark: block %s cubes x 5 tets (or as hexahedra), %s cycles, top speed %s mm/s\n' \
  "$tag" "$cycles" "$speed"
results=$out/results_$tag.txt
: > "$results"
for elform in $elforms; do
  write_deck "$elform" "$out/block_${tag}_e$elform.k"
done
for rep in $(seq 1 "$repeat"); do
  for elform in $elforms; do
    deck=$out/block_${tag}_e$elform.k
    for np in $ranks; do
      log=$out/run_${tag}_e${elform}_np${np}_r$rep.log
      line=$(run_case "$elform" "$np" "$deck" "$log")
      echo "elform=$elform np=$np rep=$rep $line" >> "$results"
      echo "  round $rep, ELFORM $elform, $np rank(s): done ($log)"
      if [ "$np" = 2 ] && [ "$pair" = 1 ]; then
        # what the machine gives two processes at once: two independent 1-rank runs (not
        # bound: each mpirun alone would bind its rank to the same first core)
        for half in a b; do
          run_case "$elform" 1 "$deck" "$out/run_${tag}_e${elform}_pair${half}_r$rep.log" \
            "_pair$half" none > "$out/pair_$half.txt" &
        done
        wait
        for half in a b; do
          echo "elform=$elform np=pair rep=$rep $(cat "$out/pair_$half.txt")" >> "$results"
        done
        echo "  round $rep, ELFORM $elform, two 1-rank runs at once: done"
      fi
    done
  done
done

/usr/bin/python3 - "$results" <<'PY'
import sys
from statistics import median
runs = []
for line in open(sys.argv[1]):
    runs.append(dict(w.split('=', 1) for w in line.split()))
def f(d, k):
    return float(d[k])
name = {'43': 'ME-FEM tet (43)', '13': 'nodal-pressure tet (13)', '10': 'standard tet (10)',
        '1': 'one-point hexahedron (1)'}
pairs = [d for d in runs if d['np'] == 'pair']
runs = [d for d in runs if d['np'] != 'pair']
cases = []                                   # (elform, np) in the order first run
for d in runs:
    if (d['elform'], d['np']) not in cases:
        cases.append((d['elform'], d['np']))
ns_of = {}                                   # (elform, np) -> {rep: ns per element-cycle}
for d in runs:
    ns_of.setdefault((d['elform'], d['np']), {})[d['rep']] = f(d, 'ns_elem')
print()
print('| element | ranks | elements | cells | cycles | analysis wall | ns/element-cycle | '
      'ns/cell-cycle | forces | halo+reductions | nodal update | output | '
      'peak memory per rank | memory per element | speed-up | force time max/min | '
      'CPU share | host steal | ns/element-cycle, all runs |')
print('|' + '---|' * 19)
for elform, np_text in cases:
    group = [d for d in runs if d['elform'] == elform and d['np'] == np_text]
    group.sort(key=lambda d: f(d, 'ns_elem'))
    d = group[(len(group) - 1) // 2]         # the median run (lower middle of an even count)
    np_ = int(np_text)
    elements = int(d['elements'])
    mem = f(d, 'mem_max')
    per_elem = mem * np_ * 1024.0 / elements          # KiB per element, all ranks
    speedup = ''
    one = ns_of.get((elform, '1'), {})
    if np_ > 1 and one:
        # core time per element-cycle = wall x ranks: speed-up = ranks x ns(1)/ns(np), per round
        ups = [np_ * one[r] / ns for r, ns in ns_of[(elform, np_text)].items() if r in one]
        if ups:
            speedup = f'{median(ups):.2f} ({min(ups):.2f}-{max(ups):.2f})'
    spread = ''
    if np_ > 1 and f(d, 'forces_min') > 0:
        spread = f'{f(d, "forces_max") / f(d, "forces_min"):.3f}'
    every = ' / '.join(f'{f(g, "ns_elem"):.0f}' for g in
                       sorted(group, key=lambda g: int(g['rep'])))
    print(f'| {name.get(elform, elform)} | {np_} | {elements} | {d["cells"]} | '
          f'{d["cycles"]} | {f(d, "analysis"):.2f} s | {f(d, "ns_elem"):.0f} | '
          f'{f(d, "ns_cell"):.0f} | {f(d, "forces"):.1f} % | {f(d, "halo"):.1f} % | '
          f'{f(d, "update"):.1f} % | {f(d, "output"):.1f} % | {mem:.0f} MiB | '
          f'{per_elem:.2f} KiB | {speedup} | {spread} | {f(d, "cpu_share"):.2f} | '
          f'{100 * median(f(g, "host_steal") for g in group):.1f} % | {every} |')
# the pair of 1-rank runs at once, per round: machine bound 2 ns(1)/ns(pair), efficiency of
# the 2-rank run against it ns(pair)/ns(2), ns(pair) the mean of the two runs
for elform in dict.fromkeys(d['elform'] for d in pairs):
    pair_ns = {}
    for d in pairs:
        if d['elform'] == elform:
            pair_ns.setdefault(d['rep'], []).append(f(d, 'ns_elem'))
    one, two = ns_of.get((elform, '1'), {}), ns_of.get((elform, '2'), {})
    bound = [2.0 * one[r] * 2 / sum(v) for r, v in pair_ns.items() if r in one and len(v) == 2]
    eff = [sum(v) / 2 / two[r] for r, v in pair_ns.items() if r in two and len(v) == 2]
    every = ' / '.join(f'{sum(v) / len(v):.0f}' for r, v in sorted(pair_ns.items(),
                                                                 key=lambda t: int(t[0])))
    text = f'\n{name.get(elform, elform)}, two 1-rank runs at once: ns/element-cycle {every}'
    if bound:
        text += (f'; machine bound of the 2-rank speed-up {median(bound):.2f} '
                 f'({min(bound):.2f}-{max(bound):.2f})')
    if eff:
        text += (f'; 2-rank run against it {100 * median(eff):.0f} % '
                 f'({100 * min(eff):.0f}-{100 * max(eff):.0f} %)')
    print(text)
# the same at the median cycle (50 % percentile of the wall time per cycle, which a few slow
# stretches of the host do not move): speed-up p50(1)/p50(np) and bound 2 p50(1)/p50(pair)
for elform in dict.fromkeys(d['elform'] for d in runs):
    p50 = {}
    for d in runs + pairs:
        if d['elform'] == elform and d.get('cycle_p50', 'nan') != 'nan':
            p50.setdefault(d['np'], {}).setdefault(d['rep'], []).append(f(d, 'cycle_p50'))
    one = {r: v[0] for r, v in p50.get('1', {}).items()}
    if not one:
        continue
    text = (f'\n{name.get(elform, elform)}, at the median cycle: 1 rank '
            f'{1e3 * median(one.values()):.1f} ms')
    for np_text in sorted(k for k in p50 if k not in ('1', 'pair')):
        times = {r: v[0] for r, v in p50[np_text].items()}
        ups = [one[r] / t for r, t in times.items() if r in one]
        text += f'; {np_text} ranks {1e3 * median(times.values()):.1f} ms'
        if ups:
            text += f', speed-up {median(ups):.2f} ({min(ups):.2f}-{max(ups):.2f})'
    bound = [4.0 * one[r] / sum(v) for r, v in
             p50.get('pair', {}).items() if r in one and len(v) == 2]
    if bound:
        text += f'; machine bound {median(bound):.2f} ({min(bound):.2f}-{max(bound):.2f})'
    print(text)
ns = {e: median(v.values()) for (e, n), v in ns_of.items() if n == '1'}
if '43' in ns and '10' in ns:
    print(f'\nME-FEM / standard cost per element-cycle on 1 rank (medians): '
          f'{ns["43"] / ns["10"]:.2f}')
if '13' in ns and '10' in ns:
    print(f'nodal-pressure / standard cost per element-cycle on 1 rank (medians): '
          f'{ns["13"] / ns["10"]:.2f}')
if '1' in ns and '10' in ns:
    print(f'hexahedron / standard tet cost per element-cycle on 1 rank (medians): '
          f'{ns["1"] / ns["10"]:.2f} (a hexahedron covers the volume of 5 tets: per unit '
          f'volume {ns["1"] / (5 * ns["10"]):.2f})')
print('(rows: the run with the median ns per element-cycle of its case, runs listed in the '
      'order made; ns per element-cycle: wall time of the cycle loop x ranks / (elements x '
      'cycles); shares: rank 0; memory: peak resident (VmHWM), max over ranks; per element: '
      'that x ranks / elements; speed-up: ranks x ns(1 rank)/ns(ranks) per round, median '
      '(range); force time max/min: the slowest rank\'s cell loop over the fastest\'s (load '
      'imbalance); CPU share: CPU time / (wall x ranks) of the whole process, well below 1 '
      'when other jobs shared the cores, which inflates the wall-time figures; host steal: '
      'median over the case\'s runs of the share of the machine\'s CPU time the host gave to '
      'others while the run wanted it (/proc/stat); at the median '
      'cycle: the 50 % percentile of the wall time per cycle, per round)')
PY
