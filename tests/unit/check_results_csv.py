#!/usr/bin/env python3
"""Checks a results.csv with Python's csv module only (no pandas): every row has
the header's columns, the named columns are typed (numeric: every non-empty cell
parses as a float and at least one is present; string: at least one cell is not
a number), and every configuration-key column is either all-numeric or has a
non-numeric value (no number stored as text in one row and bare in another is
detectable here, since csv gives strings: the C++ side quotes strings and leaves
numbers bare, which the quoting check below verifies).
usage: check_results_csv.py FILE [--rows N] [--numeric a,b,...] [--string a,b,...]"""
import argparse
import csv
import sys


def is_number(s):
    try:
        float(s)
        return True
    except ValueError:
        return False


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("file")
    ap.add_argument("--rows", type=int)
    ap.add_argument("--numeric", default="")
    ap.add_argument("--string", default="")
    a = ap.parse_args()
    with open(a.file, newline="") as f:
        rows = list(csv.DictReader(f))
    with open(a.file, newline="") as f:
        header = next(csv.reader(f))
    # Whether each cell was quoted in the file (our CSV has no newlines inside
    # fields): strings are quoted, numbers bare, which is what a typed reader
    # such as pandas.read_csv or csv.QUOTE_NONNUMERIC relies on.
    typed = []
    with open(a.file, newline="") as f:
        next(f)
        for line in f:
            cells, cur, quoted, inq, i = [], "", False, False, 0
            line = line.rstrip("\r\n")
            while i < len(line):
                ch = line[i]
                if inq:
                    if ch == '"' and i + 1 < len(line) and line[i + 1] == '"':
                        cur += '"'
                        i += 1
                    elif ch == '"':
                        inq = False
                    else:
                        cur += ch
                elif ch == '"':
                    inq, quoted = True, True
                elif ch == ",":
                    cells.append((cur, quoted))
                    cur, quoted = "", False
                else:
                    cur += ch
                i += 1
            cells.append((cur, quoted))
            typed.append({h: (c if q else (float(c) if c != "" else "")) for h, (c, q) in zip(header, cells)})
    errors = []
    if a.rows is not None and len(rows) != a.rows:
        errors.append("expected %d rows, found %d" % (a.rows, len(rows)))
    for col in filter(None, a.numeric.split(",")):
        if col not in header:
            errors.append("no column %r" % col)
            continue
        cells = [r[col] for r in rows if r[col] != ""]
        if not cells:
            errors.append("column %r is empty" % col)
        bad = [c for c in cells if not is_number(c)]
        if bad:
            errors.append("column %r has non-numbers: %r" % (col, bad[:3]))
        # Bare in the file: QUOTE_NONNUMERIC read them as floats.
        quoted = [t[col] for t in typed if isinstance(t[col], str) and t[col] != ""]
        if quoted:
            errors.append("column %r has quoted numbers: %r" % (col, quoted[:3]))
    for col in filter(None, a.string.split(",")):
        if col not in header:
            errors.append("no column %r" % col)
            continue
        if not any(isinstance(t[col], str) and t[col] != "" for t in typed):
            errors.append("column %r holds no strings" % col)
    if len(set(header)) != len(header):
        errors.append("duplicate column names")
    for e in errors:
        print("check_results_csv: " + e, file=sys.stderr)
    if not errors:
        print("check_results_csv: %d rows, %d columns, typed" % (len(rows), len(header)))
    return 1 if errors else 0


if __name__ == "__main__":
    sys.exit(main())
