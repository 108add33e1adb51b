# floor-orig-run*.md (roots_floor_report as it was) vs floor-fixed-run*.md (binomial table):
# medians over the three runs and ranges.
import statistics
def load(kind):
    runs = []
    for r in (1, 2, 3):
        rows = {}
        for l in open(f'floor-{kind}-run{r}.md'):
            c = [x.strip() for x in l.strip().strip('|').split('|')]
            if len(c) > 8 and c[1].isdigit():
                rows[(c[0], int(c[1]))] = c
        runs.append(rows)
    return runs
o = load('orig'); f = load('fixed')
print('| family | degree | floor ns (as is) | Sturm / floor (as is) | floor ns (binomial table) | Sturm / floor (binomial table) | Sturm / Auto (both) |')
print('|---|---:|---:|---:|---:|---:|---:|')
for k in o[0]:
    def s(runs, i):
        v = [float(r[k][i]) for r in runs]
        return statistics.median(v), min(v), max(v)
    on = s(o, 4); orat = s(o, 7); fn = s(f, 4); frat = s(f, 7)
    sa = [float(r[k][6]) for r in o + f]
    print(f'| {k[0]} | {k[1]} | {on[0]:.0f} | {orat[0]:.2f} ({orat[1]:.2f}-{orat[2]:.2f}) | {fn[0]:.0f} | '
          f'{frat[0]:.2f} ({frat[1]:.2f}-{frat[2]:.2f}) | {statistics.median(sa):.2f} ({min(sa):.2f}-{max(sa):.2f}) |')
