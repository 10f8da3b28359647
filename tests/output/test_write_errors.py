"""Write errors (issue 21): every output file written to /dev/full, and whole runs on a full
file system, must stop with one clear message naming the file and the system's reason, exit
with code 1 (no crash), and leave what was written before readable: the .pvd parses and lists
existing files only, the HDF5 file opens and every state /time_history lists is complete.

gfortran's run-time library does not report writes the system refuses (on /dev/full or a full
tmpfs its WRITE, FLUSH and CLOSE return 0), so before this test the histories were written
"successfully" into nothing and the run exited 0 (doc/verification.md).

1. /dev/full in place of each history file (glstat, nodout, rwforc, rbdout, rcforc) and of the
   first .vtu of a short contact run that writes all of them; and as the run's log (standard
   output).
2. A tmpfs of 300 KiB to 3 MiB as the output directory of the copper Taylor bar (coarse mesh,
   16 states) on 1 and 2 ranks: the disk fills at a different file each time. Skipped with a
   message where mounting a tmpfs is not allowed.
"""
import os
import subprocess
import sys
import xml.etree.ElementTree as ET

import h5py
import numpy as np

ROOT = os.path.abspath(os.path.join(os.path.dirname(__file__), '..', '..'))
sys.path.insert(0, os.path.join(ROOT, 'tests', 'verification'))
sys.path.insert(0, os.path.join(ROOT, 'tests', 'bench'))
from deck_writer import Checks, write_deck, run                           # noqa: E402
from explicit_cases import all_histories_blocks                           # noqa: E402
import taylor_copper as tc                                                # noqa: E402

checks = Checks('write_errors')
OUT = os.path.join(ROOT, 'tests', 'out', 'write_errors')
os.makedirs(OUT, exist_ok=True)


def results_intact(out, stem, name):
    """The .pvd parses and lists existing files; the HDF5 file's listed states are complete."""
    pvd = os.path.join(out, stem + '.pvd')
    listed = []
    if os.path.exists(pvd):
        try:
            listed = [d.get('file') for d in ET.parse(pvd).iter('DataSet')]
        except ET.ParseError as error:
            checks.check(False, '%s: the .pvd parses' % name, str(error))
            return
    missing = [f for f in listed if not os.path.isfile(os.path.join(out, f))]
    complete = True
    h5 = os.path.join(out, stem + '.h5')
    if os.path.exists(h5) and os.path.getsize(h5) > 0:
        try:
            with h5py.File(h5, 'r') as h:
                nnode = h['mesh/coordinates'].shape[0] if 'mesh/coordinates' in h else 0
                for k in (h['time_history/step'][()] if 'time_history/step' in h else []):
                    for field in h['states/%06d/point' % k].values():
                        complete = complete and field.shape[0] == nnode and \
                            bool(np.all(np.isfinite(field[()])))
        except (OSError, KeyError) as error:
            complete = False
            print('    %s: %s' % (name, error))
    checks.check(not missing and complete, '%s: the .pvd lists existing files only and the '
                 'HDF5 states listed are complete' % name, 'missing %s, h5 %s'
                 % (missing[:3], complete))


# ---- 1. /dev/full in place of one file ---------------------------------------------------
deck = os.path.join(OUT, 'all_histories.k')
write_deck(deck, all_histories_blocks(1.0e-4), title='all_histories')
for target in ('glstat', 'nodout', 'rwforc', 'rbdout', 'rcforc', 'all_histories_000000.vtu'):
    out = os.path.join(OUT, 'full_' + target.split('.')[0])
    subprocess.run(['rm', '-rf', out])
    os.makedirs(out)
    os.symlink('/dev/full', os.path.join(out, target))
    rc, text = run(deck, out)
    expected = 'cannot write %s' % ('history file ' + os.path.join(out, target)
                                    if '.' not in target else os.path.join(out, target))
    reason = 'No space left on device' in text or 'reached the disk' in text
    checks.check(rc == 1 and expected in text and reason, '%s on /dev/full: the run stops with '
                 'exit code 1 naming the file and the reason' % target,
                 'rc %d: %s' % (rc, text[-400:]))
    results_intact(out, 'all_histories', target + ' on /dev/full')

# ---- the log (standard output) on /dev/full ------------------------------------------------
out = os.path.join(OUT, 'full_log')
subprocess.run(['rm', '-rf', out])
with open('/dev/full', 'w') as log:
    p = subprocess.run([os.path.join(ROOT, 'bin', 'mefem'), '-o', out, deck], stdout=log,
                       stderr=subprocess.PIPE, text=True,
                       env=dict(os.environ, OMPI_ALLOW_RUN_AS_ROOT='1',
                                OMPI_ALLOW_RUN_AS_ROOT_CONFIRM='1'))
checks.check(p.returncode == 1 and 'cannot write the log (standard output): No space left on '
             'device' in p.stderr, 'the log on /dev/full: the run stops with exit code 1 and '
             'the reason on standard error', 'rc %d: %s' % (p.returncode, p.stderr[-300:]))

# ---- 2. a full file system ---------------------------------------------------------------
mount_point = os.path.join(OUT, 'tmpfs')
os.makedirs(mount_point, exist_ok=True)
subprocess.run(['umount', mount_point], capture_output=True)
probe_mount = subprocess.run(['mount', '-t', 'tmpfs', '-o', 'size=64k', 'tmpfs', mount_point],
                             capture_output=True, text=True)
if probe_mount.returncode != 0:
    print('    SKIPPED the full-disk runs: mounting a tmpfs is not allowed here (%s)'
          % probe_mount.stderr.strip())
else:
    subprocess.run(['umount', mount_point])
    taylor = os.path.join(OUT, 'taylor_full.k')
    tc.write_deck(taylor, 10, 'coarse', plots=16)
    runs = clean = 0
    for ranks in (1, 2):
        for size in ('300k', '700k', '1200k', '2m', '3m'):
            subprocess.run(['mount', '-t', 'tmpfs', '-o', 'size=' + size, 'tmpfs', mount_point],
                           check=True)
            try:
                out = os.path.join(mount_point, 'out')
                rc, text = run(taylor, out, ranks=ranks)
                runs += 1
                name = 'full disk %s, %d rank(s)' % (size, ranks)
                stopped = rc == 1 and 'mefem: error: ' in text and \
                    ('No space left on device' in text or 'reached the disk' in text or
                     'cannot write' in text)
                checks.check(stopped, '%s: stops with exit code 1 and a message naming the file'
                             % name, 'rc %d: %s' % (rc, text[-400:]))
                clean += stopped
                results_intact(out, 'taylor_full', name)
            finally:
                subprocess.run(['umount', mount_point])
    print('    full-disk runs: %d, stopped cleanly: %d' % (runs, clean))
checks.exit()
