"""The units check of the model summary (src/model/model_summary.f90): a deck's densities and
moduli are read in each consistent unit system LS-DYNA users work in; the summary names the
systems that give every material a real solid's density (10-3e4 kg/m^3) and wave speed
(5-2e4 m/s), and a material that fits none is warned with its wave speed in deck units.
1. aluminium in mm, t, s, MPa (input/taylor_bar.k): "mm, t, s, MPa";
2. the same with the SI density 7850 (a common slip): a warning naming the material, its wave
   speed sqrt(E/7850) (deck units: 3, for aluminium in MPa) and the SI-density-with-MPa hint;
   no "units:" line;
3. steel in m, kg, s, Pa and in mm, kg, ms, GPa: those systems;
4. rubber (*MAT_MOONEY-RIVLIN_RUBBER A 0.5, B 0.1 MPa, 1.1e-9 t/mm^3): "mm, t, s, MPa".
"""
import os
import re
import subprocess
import sys

ROOT = os.environ.get('MEFEM_ROOT', os.path.join(os.path.dirname(__file__), '..', '..'))
OUT = os.path.join(ROOT, 'tests', 'out', 'decks')
os.makedirs(OUT, exist_ok=True)
sys.path.insert(0, os.path.join(ROOT, 'tests', 'verification'))
from deck_writer import Checks  # noqa: E402

checks = Checks('units check')
check = checks.check


def check_deck(text_of_deck, name):
    path = os.path.join(OUT, name + '.k')
    with open(path, 'w') as f:
        f.write(text_of_deck)
    run = subprocess.run([os.path.join(ROOT, 'bin', 'mefem'), '--check', path],
                         capture_output=True, text=True)
    return run.returncode, run.stdout + run.stderr


def tet_deck(scale, material):
    """One tetrahedron of edge `scale` with the material card given."""
    return '\n'.join(['*KEYWORD', '*NODE',
                      '%8d%16.6g%16.6g%16.6g' % (1, 0, 0, 0), '%8d%16.6g%16.6g%16.6g' % (2, scale, 0, 0),
                      '%8d%16.6g%16.6g%16.6g' % (3, 0, scale, 0), '%8d%16.6g%16.6g%16.6g' % (4, 0, 0, scale),
                      '*ELEMENT_SOLID', '%8d%8d%8d%8d%8d%8d' % (1, 1, 1, 2, 3, 4),
                      '*PART', 'block', '%10d%10d%10d' % (1, 1, 1), '*SECTION_SOLID',
                      '%10d%10d' % (1, 10)] + material + ['*END']) + '\n'


with open(os.path.join(ROOT, 'input', 'taylor_bar.k')) as f:
    taylor = f.read()
rc, text = check_deck(taylor, 'units_taylor')
check(rc == 0 and 'units: the materials fit mm, t, s, MPa' in text, 'the Taylor bar deck: '
      'mm, t, s, MPa', text[-400:])
density = re.search(r'^\*MAT_PIECEWISE_LINEAR_PLASTICITY\n(?:\$.*\n)*(.{10})(.{10})', taylor,
                    re.M)
slipped = taylor.replace(density.group(0), density.group(0)[:-10] + '%10.4g' % 7850.0)
rc, text = check_deck(slipped, 'units_slip')
m = re.search(r'material 1: density 7850 and modulus (\S+) fit none of the consistent unit '
              r'systems \(.*psi\): their wave speed sqrt\(E/rho\) is (\S+) length', text)
check(rc == 0 and m is not None and 'SI density with MPa' in text and
      abs(float(m.group(2)) / (float(m.group(1)) / 7850.0) ** 0.5 - 1) < 1e-5 and
      'units: the materials fit' not in text,
      'SI density with MPa moduli: warned with its wave speed sqrt(E/7850), no system named',
      text[-600:])
rc, text = check_deck(tet_deck(0.01, ['*MAT_ELASTIC', '%10d%10.4g%10.4g%10.4g' % (1, 7850.0, 2.1e11, 0.3)]),
                      'units_si')
check(rc == 0 and 'units: the materials fit m, kg, s, Pa' in text, 'steel in SI', text[-300:])
rc, text = check_deck(tet_deck(10.0, ['*MAT_ELASTIC', '%10d%10.4g%10.4g%10.4g' % (1, 7.85e-6, 210.0, 0.3)]),
                      'units_gpa')
check(rc == 0 and 'units: the materials fit mm, kg, ms, GPa' in text, 'steel in mm, kg, ms, GPa',
      text[-300:])
rc, text = check_deck(tet_deck(10.0, ['*MAT_MOONEY-RIVLIN_RUBBER',
                                      '%10d%10.4g%10.4g%10.4g%10.4g' % (1, 1.1e-9, 0.499, 0.5, 0.1)]),
                      'units_rubber')
check(rc == 0 and 'units: the materials fit mm, t, s, MPa' in text, 'rubber in mm, t, s, MPa',
      text[-300:])
checks.exit()
