#!/usr/bin/python3
"""Memory per rank of an explicit run (doc/performance.md "Memory"): runs bin/mefem on a deck
on P ranks and samples every rank's /proc/PID/status and /proc/PID/smaps_rollup every 50 ms.
Prints per rank the peak resident set (VmHWM, what the log reports: it counts every page of
the node-shared window the rank touched, its own and other ranks'), the peak proportional set
size (Pss: shared pages divided among the ranks that map them, the rank's share of the node)
with its private, shared-memory and file parts at that moment, and the peak private (anonymous)
resident memory.

usage: /usr/bin/python3 tests/bench/memory_per_rank.py DECK [--ranks 1 2 4 8]
       [--mefem bin/mefem] [--out /tmp/memory_per_rank]
A block deck: tests/bench/generate_block_deck.py 30 30 45 --tets 5 block.k, with
*CONTROL_TERMINATION ENDCYC 20 added before *END.
"""
import argparse
import os
import subprocess
import sys
import time

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))


def read_kib(path, keys):
    """The given 'Key:' fields of a /proc file, in KiB (missing: 0)."""
    values = dict.fromkeys(keys, 0)
    try:
        with open(path) as f:
            for line in f:
                name = line.split(':')[0]
                if name in values:
                    values[name] = int(line.split()[1])
    except OSError:
        pass
    return values


def children_running(pattern):
    """PIDs of processes whose command line contains pattern."""
    out = subprocess.run(['pgrep', '-f', pattern], capture_output=True, text=True).stdout
    return [int(p) for p in out.split()]


def run(deck, ranks, mefem, out):
    outdir = os.path.join(out, 'np%d' % ranks)
    cmd = [mefem, '-o', outdir, deck]
    if ranks > 1:
        cmd = ['mpirun', '--allow-run-as-root', '--oversubscribe', '-np', str(ranks)] + cmd
    env = dict(os.environ, OMPI_ALLOW_RUN_AS_ROOT='1', OMPI_ALLOW_RUN_AS_ROOT_CONFIRM='1')
    proc = subprocess.Popen(cmd, stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True,
                            env=env)
    peak = {}
    pattern = '%s -o %s' % (mefem, outdir)
    while proc.poll() is None:
        for pid in children_running(pattern):
            status = read_kib('/proc/%d/status' % pid, ['VmHWM', 'RssAnon'])
            pss = read_kib('/proc/%d/smaps_rollup' % pid,
                           ['Pss', 'Pss_Anon', 'Pss_Shmem', 'Pss_File'])
            p = peak.setdefault(pid, {'VmHWM': 0, 'RssAnon': 0, 'Pss': 0, 'parts': (0, 0, 0)})
            p['VmHWM'] = max(p['VmHWM'], status['VmHWM'])
            p['RssAnon'] = max(p['RssAnon'], status['RssAnon'])
            if pss['Pss'] > p['Pss']:
                p['Pss'] = pss['Pss']
                p['parts'] = (pss['Pss_Anon'], pss['Pss_Shmem'], pss['Pss_File'])
        time.sleep(0.05)
    text = proc.stdout.read()
    if proc.returncode != 0:
        print(text[-2000:])
        raise SystemExit('run on %d ranks failed' % ranks)
    # the ranks are the processes that ran the deck (mpirun's own process holds almost nothing)
    ranks_seen = sorted((p for p in peak.values() if p['Pss'] > 30 * 1024),
                        key=lambda p: -p['VmHWM'])
    return ranks_seen


def main(argv):
    ap = argparse.ArgumentParser(description=__doc__.split('\n')[0])
    ap.add_argument('deck')
    ap.add_argument('--ranks', type=int, nargs='+', default=[1, 2, 4, 8])
    ap.add_argument('--mefem', default=os.path.join(ROOT, 'bin', 'mefem'))
    ap.add_argument('--out', default='/tmp/memory_per_rank')
    args = ap.parse_args(argv)
    print('MiB per rank, the processes by peak VmHWM, largest first: peak VmHWM | peak Pss '
          '(private / shared window / files at that moment) | peak private resident')
    for ranks in args.ranks:
        for i, p in enumerate(run(os.path.abspath(args.deck), ranks, args.mefem, args.out)):
            a, m, f = p['parts']
            print('%d ranks, process %d: %7.1f | %7.1f (%.1f / %.1f / %.1f) | %7.1f' % (
                ranks, i, p['VmHWM'] / 1024, p['Pss'] / 1024, a / 1024, m / 1024, f / 1024,
                p['RssAnon'] / 1024))


if __name__ == '__main__':
    main(sys.argv[1:])
