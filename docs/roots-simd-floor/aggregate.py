# Aggregates run1..3.md of roots_simd_floor_report: per row and method, the median over the
# three runs of each run's median Sturm / method ratio, and the range of the three.
import re, statistics, sys, pathlib
d = pathlib.Path(sys.argv[1] if len(sys.argv) > 1 else '.')
runs = []
for r in (1, 2, 3):
    rows = {}
    header = None
    for line in (d / f'run{r}.md').read_text().splitlines():
        if not line.startswith('|'):
            continue
        cells = [c.strip() for c in line.strip('|').split('|')]
        if cells[0] == 'family':
            header = cells
            continue
        rows[(cells[0], int(cells[1]))] = cells
    runs.append(rows)
names = [h.split(':')[0] for h in header[5:-3]]
keys = list(runs[0].keys())
print('| family | degree | Sturm / Auto | ' + ' | '.join(names) + ' |')
print('|---|---:|---:|' + '---:|' * len(names))
for k in keys:
    sa = [float(run[k][4]) for run in runs]
    out = [f'{statistics.median(sa):.2f} ({min(sa):.2f}-{max(sa):.2f})']
    for i in range(len(names)):
        vals = [float(re.search(r'ns ([0-9.]+)', run[k][5 + i]).group(1)) for run in runs]
        ns = [float(run[k][5 + i].split(' ns')[0]) for run in runs]
        out.append(f'{statistics.median(vals):.2f} ({min(vals):.2f}-{max(vals):.2f}), {statistics.median(ns):.0f} ns')
    print(f'| {k[0]} | {k[1]} | ' + ' | '.join(out) + ' |')
print()
print('Sturm ns (median of runs):', {f'{k[0]}{k[1]}': statistics.median(float(run[k][3]) for run in runs) for k in keys})
print('agreement (run 1): scalar floor vs Auto, then each variant vs scalar floor within 1e-9 / bit-identical')
for k in keys:
    print(k, runs[0][k][-3], '|', runs[0][k][-2], '|', runs[0][k][-1])
