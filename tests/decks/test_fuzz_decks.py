"""Mutated decks (issue 21): a hundred decks (MEFEM_FUZZ_MUTANTS) made from the project's good
decks by random edits (a fixed seed: the same decks every run) are checked by both builds
(`--check`). Each
must end within a few seconds with exit code 0 (accepted) or 1 (input errors), never a crash
(a signal, an MPI abort, a run-time error of the debug build) or a hang.

Edits: delete, duplicate or swap lines; replace a character by a digit, letter, sign, comma,
blank, tab, '*', '$' or a control byte; replace a number by an extreme one (0, -1, 1e308,
1e400, -1e-320, 2147483648, NaN); cut the deck short; join two lines. Several edits per deck.
"""
import os
import random
import subprocess
import sys
import tempfile

ROOT = os.path.abspath(os.path.join(os.path.dirname(__file__), '..', '..'))
sys.path.insert(0, os.path.join(ROOT, 'tests', 'verification'))
from deck_writer import Checks  # noqa: E402

checks = Checks('fuzz_decks')
SEED = 20261127
MUTANTS = int(os.environ.get('MEFEM_FUZZ_MUTANTS', '100'))     # each build checks them all
TIMEOUT = 20                                                   # s per check
SOURCES = [os.path.join(ROOT, 'tests', 'decks', 'good', f) for f in
           sorted(os.listdir(os.path.join(ROOT, 'tests', 'decks', 'good'))) if f.endswith('.k')]
SOURCES += [os.path.join(ROOT, 'input', 'taylor_bar.k')]
EXTREMES = ['0', '-1', '1e308', '1e400', '-1e-320', '2147483648', '-2147483649', 'NaN', 'inf',
            '1.7976931348623157e308', '99999999', '1,2', '']
CHARS = list('0123456789abcXYZ+-.,*$ \t') + ['\x00', '\x07', '\x1b']


def mutate(lines, rng):
    """A few random edits of a deck's lines."""
    lines = list(lines)
    for _ in range(rng.randint(1, 4)):
        if not lines:
            break
        k = rng.randrange(len(lines))
        kind = rng.randrange(8)
        if kind == 0:
            del lines[k]
        elif kind == 1:
            lines.insert(k, lines[k])
        elif kind == 2:
            j = rng.randrange(len(lines))
            lines[k], lines[j] = lines[j], lines[k]
        elif kind == 3 and lines[k]:
            c = rng.randrange(len(lines[k]))
            lines[k] = lines[k][:c] + rng.choice(CHARS) + lines[k][c + 1:]
        elif kind == 4:
            words = lines[k].replace(',', ' ').split()
            if words and not lines[k].startswith(('*', '$')):
                w = rng.choice(words)
                lines[k] = lines[k].replace(w, rng.choice(EXTREMES), 1)
        elif kind == 5:
            del lines[rng.randrange(len(lines)):]
        elif kind == 6 and k + 1 < len(lines):
            lines[k] = lines[k] + lines.pop(k + 1)
        else:
            lines[k] = lines[k][:rng.randrange(len(lines[k]) + 1)]
    return lines


rng = random.Random(SEED)
decks = []
for n in range(MUTANTS):
    source = rng.choice(SOURCES)
    with open(source, encoding='latin-1') as f:
        decks.append((os.path.basename(source), mutate(f.read().split('\n'), rng)))

work = tempfile.mkdtemp(prefix='mefem_fuzz_')
for exe in ('mefem_debug', 'mefem'):
    counts = {'accepted': 0, 'rejected': 0, 'crashed': 0, 'hung': 0}
    bad = []
    for n, (source, lines) in enumerate(decks):
        path = os.path.join(work, 'mutant_%03d.k' % n)
        with open(path, 'w', encoding='latin-1') as f:
            f.write('\n'.join(lines))
        try:
            p = subprocess.run([os.path.join(ROOT, 'bin', exe), '--check', path],
                               capture_output=True, timeout=TIMEOUT, cwd=work,
                               env=dict(os.environ, OMPI_ALLOW_RUN_AS_ROOT='1',
                                        OMPI_ALLOW_RUN_AS_ROOT_CONFIRM='1'))
            rc = p.returncode
            if rc == 0:
                counts['accepted'] += 1
            elif rc == 1 and b'Error termination' not in p.stderr and \
                    b'Fortran runtime error' not in p.stderr and b'Backtrace' not in p.stderr:
                counts['rejected'] += 1
            else:
                counts['crashed'] += 1
                bad.append('%s (from %s): exit %d: %s' % (os.path.basename(path), source, rc,
                                                         p.stderr.decode('latin-1')[-300:]))
        except subprocess.TimeoutExpired:
            counts['hung'] += 1
            bad.append('%s (from %s): no end within %d s' % (os.path.basename(path), source,
                                                            TIMEOUT))
    print('    %s: %d mutants, accepted %d, rejected %d, crashed %d, hung %d' % (
        exe, len(decks), counts['accepted'], counts['rejected'], counts['crashed'],
        counts['hung']))
    checks.check(not bad, '%s: %d mutated decks, no crash and no hang' % (exe, len(decks)),
                 '\n'.join(bad[:5]) + ('\n(deck files kept in %s)' % work if bad else ''))
if checks.failed == 0:                 # (kept for a look when something failed)
    subprocess.run(['rm', '-rf', work])
checks.exit()
