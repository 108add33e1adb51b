# Aggregates parts-run1..3.md of roots_simd_floor_report --parts: per row, the median over the
# three runs of each ns figure, and the scalar / SIMD ratios with their range over the runs.
import statistics, sys, pathlib
d = pathlib.Path(sys.argv[1] if len(sys.argv) > 1 else '.')
runs = []
for r in (1, 2, 3):
    rows = {}
    for line in (d / f'parts-run{r}.md').read_text().splitlines():
        c = [x.strip() for x in line.strip('|').split('|')]
        if len(c) < 7 or c[0] in ('family',) or c[0].startswith('---'):
            continue
        rows[tuple(c[:4])] = c[4:]
    runs.append(rows)
print('| family | degree | part | mode | scalar ns | wave ns | scalar / wave | matrix ns | scalar / matrix |')
print('|---|---:|---|---|---:|---:|---:|---:|---:|')
def med(vals):
    return statistics.median(vals)
for k in runs[0]:
    sc = [float(run[k][0]) for run in runs]
    out = [f'{med(sc):.1f}']
    for i in (1, 2):
        if runs[0][k][i] == '-':
            out += ['-', '-']
            continue
        ns = [float(run[k][i].split(' (')[0]) for run in runs]
        ra = [float(run[k][i].split('(')[1].rstrip(')')) for run in runs]
        out += [f'{med(ns):.1f}', f'{med(ra):.2f} ({min(ra):.2f}-{max(ra):.2f})']
    print('| ' + ' | '.join(k) + ' | ' + ' | '.join(out) + ' |')
