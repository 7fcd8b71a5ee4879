#!/usr/bin/env python3
"""How the coincidence constants of `rigid` were chosen (docs/method.md,
"Coincidence"): reads answer files written with the gate off
(`DIAG_NOGATE=1 DIAG_PERSEED=1 DIAG_OUT=DIR cargo test -p vref-sim --test
rigid_answers -- --ignored diag`: real training sets as NAME.jsonl, unrelated
views as null-*.jsonl) and prints, for each pair of thresholds (significance
-log10 NFA below ts and margin below tm: the partner is capped at CAP, 0.45),
the share of unrelated answers still `ok` and the largest rise of a real
set's ECE.

    python3 tools/coincidence-gate.py DIR
"""
import glob, json, os, sys
d=sys.argv[1]; cap=float(os.environ.get("CAP","0.45"))
def rows(p): return [json.loads(l) for l in open(p)]
null=[r for p in glob.glob(d+'/null-*.jsonl') for r in rows(p)]
real={os.path.basename(p)[:-6]:rows(p) for p in glob.glob(d+'/*.jsonl') if not os.path.basename(p).startswith('null-')}
def s(r): return r['significance'] if r['significance'] is not None else -99
def g(r): return r['margin'] if r['margin'] is not None else 99
def ece(ans, bins=10):
    cnt=[0]*bins; cs=[0]*bins; rt=[0]*bins
    for c,ok in ans:
        b=min(int(c*bins),bins-1); cnt[b]+=1; cs[b]+=c; rt[b]+=ok
    return sum(cnt[b]/len(ans)*abs(cs[b]/cnt[b]-rt[b]/cnt[b]) for b in range(bins) if cnt[b])
base={k:ece([(r['confidence'],r['correct']) for r in v]) for k,v in real.items()}
for ts in [-3,-2.75,-2.5,-2.25,-2,-1.75,-1.5]:
  for tm in [-0.5,0,0.25,0.5]:
    fail=lambda r: r['matched'] and s(r)<ts and g(r)<tm
    ok=sum(1 for r in null if r['matched'] and r['confidence']>=0.5 and not fail(r))
    rise={k:ece([((min(r['confidence'],cap) if fail(r) else r['confidence']), r['correct']) for r in v])-base[k] for k,v in real.items()}
    w=max(rise,key=rise.get)
    print(f"ts {ts} tm {tm} ok {100*ok/len(null):.2f}% worst rise {rise[w]:.3f} ({w}) worst ECE {max(base[k]+rise[k] for k in real):.3f}")
