"""The card layouts of src/input/card_layouts.f90 (the table the readers take fields from)
against the keyword manual's tables, doc/keywords.md: for every keyword of the table, its
section's tables (card 1, 2, ... in order, or the Card column) list the same fields, each with
the same columns, type, default (a number, "required", or "X (0 = default)" for a field whose 0
means its default), and every field the manual does not mark "not read" (or type A, text) is
in the table. (The values the readers take from the table are checked by
tests/unit/test_keyword_handlers.f90.)
"""
import os
import re
import sys

ROOT = os.environ.get('MEFEM_ROOT', os.path.join(os.path.dirname(__file__), '..', '..'))
sys.path.insert(0, os.path.join(ROOT, 'tests', 'verification'))
from deck_writer import Checks  # noqa: E402

checks = Checks('card layouts')
ROW = re.compile(r"field_layout_t\('([\w-]+)', (\d+), '(\w+)', (\d+), (\d+), '([IF])', ([-+0-9.e]+)_wp, "
                 r"\.(true|false)\., \.(true|false)\.\)")


def layout_table():
    """[(keyword, card, name, first, last, kind, default, required, zero_is_default)]."""
    text = open(os.path.join(ROOT, 'src', 'input', 'card_layouts.f90')).read()
    return [(k, int(c), n, int(a), int(b), t, float(d), r == 'true', z == 'true')
            for k, c, n, a, b, t, d, r, z in ROW.findall(text)]


def manual_tables(keyword):
    """The tables of the manual's section of keyword: [[(card or None, cells)]]."""
    lines = open(os.path.join(ROOT, 'doc', 'keywords.md')).read().splitlines()
    heading = re.compile(r'^#### .*\*%s(?![A-Z0-9_])' % re.escape(keyword))
    start = next((i for i, line in enumerate(lines) if heading.match(line)), None)
    if start is None:
        return None
    tables, current, has_card = [], None, False
    for line in lines[start + 1:]:
        if line.startswith('#### ') or line.startswith('## ') or line.startswith('### '):
            break
        if line.startswith('|'):
            cells = [c.strip() for c in line.strip().strip('|').split('|')]
            if current is None:
                current = []
                has_card = cells[0] == 'Card'
                tables.append(current)
                continue
            if set(cells[0]) <= set('-'):
                continue
            if has_card:                   # optional cards A, B, ... are 101, 102, ...
                label = cells[0]                           # '2...', '3 (NSIDEX > 0 only)':
                number = re.match(r'(\d+)', label)          # card 2, card 3
                card = int(number.group(1)) if number else (
                    100 + ord(label) - ord('A') + 1 if len(label) == 1 and label.isalpha()
                    else None)
                current.append((card, cells[1:]))
            else:
                current.append((None, cells))
        else:
            current = None
    return tables


def parse_default(text):
    """(value or None, required, zero_is_default) of a manual Default cell."""
    required = text.startswith('required')
    zero = '(0 = default)' in text
    m = re.match(r'\s*([-+]?[0-9.]+(?:e[-+]?\d+)?)', text)
    return (float(m.group(1)) if m else None), required, zero


rows = layout_table()
declared = int(re.search(r'N_LAYOUT_FIELDS = (\d+)',
                         open(os.path.join(ROOT, 'src', 'input', 'card_layouts.f90')).read()).group(1))
checks.check(len(rows) == declared, 'every row of the table is read here (%d fields)' % len(rows),
             '%d of %d' % (len(rows), declared))
for keyword in sorted({r[0] for r in rows}):
    tables = manual_tables(keyword)
    if tables is None:
        checks.check(False, '*%s: the manual has its section' % keyword)
        continue
    documented = {}                        # (card, name) -> (first, last, type, default cell)
    unread = []
    for index, table in enumerate(tables):
        for card, cells in table:
            card = card if card is not None else index + 1
            # 'NID / NSID / PID': one field named by the keyword's form (the table: the first)
            names = [n.split('/')[0].strip() for n in cells[0].split(',')]
            series = re.match(r'([A-Z]+)(\d+) \.\.\. \1(\d+)$', cells[0])   # EPS1 ... EPS8
            if series:
                names = ['%s%d' % (series.group(1), i)
                         for i in range(int(series.group(2)), int(series.group(3)) + 1)]
            columns = re.match(r'(\d+)-(\d+)', cells[1]) if len(cells) > 1 else None
            # text fields (type A: a part's HEADING) are read by the reader, not the table
            if 'not read' in cells[-1] or not columns or (len(cells) > 2 and cells[2] == 'A'):
                unread.append((card, cells[0]))
                continue
            first, last = int(columns.group(1)), int(columns.group(2))
            width = (last - first + 1) // len(names)
            for k, name in enumerate(names):
                documented[card, name] = (first + k * width, first + (k + 1) * width - 1,
                                          cells[2], cells[3], cells[0])
    table_rows = [r for r in rows if r[0] == keyword]
    mismatches = []
    for _, card, name, first, last, kind, default, required, zero in table_rows:
        doc = documented.get((card, name))
        if doc is None:
            mismatches.append('card %d %s: not in the manual\'s tables' % (card, name))
            continue
        value, doc_required, doc_zero = parse_default(doc[3])
        dependent = re.match(r'([A-Z][A-Z0-9]*)\b', doc[3])       # 'T1 (0 = default)': the
        if dependent and any(dependent.group(1) == r[2] for r in rows if r[0] == keyword):
            value, doc_zero = default, zero                       # reader applies it
        if (doc[0], doc[1]) != (first, last):
            mismatches.append('%s: columns %d-%d, manual %d-%d' % (name, first, last, doc[0],
                                                                    doc[1]))
        if doc[2] != kind and not (doc[2] == '' and ',' in doc[4]):   # (a group, mixed types)
            mismatches.append('%s: type %s, manual %s' % (name, kind, doc[2]))
        if doc_required != required or (not required and (value is None or
                                                          abs(value - default) >
                                                          1e-12 * max(1.0, abs(default)))):
            mismatches.append('%s: default %g%s, manual "%s"' % (
                name, default, ' required' if required else '', doc[3]))
        if doc_zero != zero:
            mismatches.append('%s: 0 = default %s, manual "%s"' % (name, zero, doc[3]))
    missing = [name for (card, name) in documented
               if not any(r[1] == card and r[2] == name for r in table_rows)]
    checks.check(not mismatches and not missing, '*%s: the manual\'s fields are the table\'s '
                 '(%d fields)' % (keyword, len(table_rows)),
                 '; '.join(mismatches + ['%s read in the manual, not in the table' % m
                                         for m in missing]))
checks.exit()
