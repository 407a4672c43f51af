"""Write height10m.obj: a 2,237 x 2,237 height field (9,999,392 triangles), the
10-million-triangle mesh of docs/benchmarks.md. Needs numpy; about 30 s and 390 MB."""
import numpy as np

n = 2237
x = np.linspace(-1, 1, n, dtype=np.float32)
X, Z = np.meshgrid(x, x)
Y = (0.1 * np.sin(7 * X) * np.cos(5 * Z) + 0.05 * np.sin(23 * X + 11 * Z)).astype(np.float32)
with open("height10m.obj", "w") as f:
    np.savetxt(f, np.stack([X.ravel(), Y.ravel(), Z.ravel()], 1), fmt="v %.5f %.5f %.5f")
    I, J = np.meshgrid(np.arange(n - 1), np.arange(n - 1))
    a = (J * n + I).ravel() + 1
    faces = np.empty((2 * len(a), 3), dtype=np.int64)
    faces[0::2] = np.stack([a, a + n, a + 1], 1)
    faces[1::2] = np.stack([a + 1, a + n, a + n + 1], 1)
    np.savetxt(f, faces, fmt="f %d %d %d")
