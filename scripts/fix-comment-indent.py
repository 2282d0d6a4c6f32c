#!/usr/bin/env python3
# Part of `make format` (scripts/format.sh): clang-format 14 moves the first line of a
# block comment (aligning trailing comments, or putting a comment before a #pragma on
# column 0) but leaves its continuation lines where they were. This puts them back under
# the first line; clang-format then leaves them alone, so `make format-check` is stable.
import sys
changed = 0
for path in sys.argv[1:]:
    lines = open(path).read().split('\n')
    i = 0
    out = False
    while i < len(lines):
        l = lines[i]
        m = l.find('/*')
        if m > 0 and l[:m].strip() and '*/' not in l[m:] and '"' not in l[:m] and not l.rstrip().endswith('\\'):
            col = m
            j = i + 1
            while j < len(lines):
                s = lines[j].lstrip()
                if s.startswith('*') and not s.startswith('*/'):
                    new = ' ' * (col + 1) + s
                else:
                    new = ' ' * (col + 3) + s
                if s.startswith('*/'):
                    new = ' ' * (col + 1) + s
                if new != lines[j]:
                    lines[j] = new; out = True; changed += 1
                if '*/' in s:
                    break
                j += 1
            i = j + 1
            continue
        # A comment of its own lines whose first line clang-format moved (e.g. onto a
        # #pragma's column 0): its ' * ' lines follow it.
        if m >= 0 and not l[:m].strip() and '*/' not in l[m:]:
            j = i + 1
            while j < len(lines):
                s = lines[j].lstrip()
                if not s.startswith('*'):
                    break
                new = ' ' * (m + 1) + s
                if new != lines[j]:
                    lines[j] = new; out = True; changed += 1
                if '*/' in s:
                    break
                j += 1
            i = j + 1 if j > i + 1 else i + 1
            continue
        i += 1
    if out:
        open(path, 'w').write('\n'.join(lines))
print(changed, file=sys.stderr)
