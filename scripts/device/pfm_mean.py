import sys, numpy as np
def read(path):
    with open(path, 'rb') as f:
        kind = f.readline().strip(); w, h = map(int, f.readline().split()); scale = float(f.readline())
        data = np.frombuffer(f.read(), dtype='<f4' if scale < 0 else '>f4')
    return data.reshape(h, w, 3 if kind == b'PF' else 1)
for p in sys.argv[1:]:
    a = read(p); m = a.reshape(-1, a.shape[2]).mean(0)
    print(f"{p.split('/')[-1]:48s} mean " + " ".join(f"{v:.5f}" for v in m) + f"  nonfinite {int((~np.isfinite(a)).sum())}  zero-px {int((a.sum(2)==0).sum())}")
