# Turns a binary PLY mesh (float x y z, uchar-int triangles, as `lsw demo` writes it) A degrees
# about z, then B about x, and writes it as ASCII PLY. Usage: turn_ply.py IN.ply OUT.ply A B
import math, struct, sys
d = open(sys.argv[1], 'rb').read()
end = d.index(b'end_header\n') + len(b'end_header\n')
head = d[:end].decode().split('\n')
nv = int(next(l for l in head if l.startswith('element vertex')).split()[2])
nf = int(next(l for l in head if l.startswith('element face')).split()[2])
V = [struct.unpack_from('<3f', d, end + 12 * i) for i in range(nv)]
o = end + 12 * nv
F = [struct.unpack_from('<3i', d, o + 13 * i + 1) for i in range(nf)]
a, b = (math.radians(float(x)) for x in sys.argv[3:5])
with open(sys.argv[2], 'w') as out:
    out.write('ply\nformat ascii 1.0\nelement vertex %d\nproperty float x\nproperty float y\n'
              'property float z\nelement face %d\nproperty list uchar int vertex_indices\n'
              'end_header\n' % (nv, nf))
    for x, y, z in V:
        x, y = x * math.cos(a) - y * math.sin(a), x * math.sin(a) + y * math.cos(a)
        y, z = y * math.cos(b) - z * math.sin(b), y * math.sin(b) + z * math.cos(b)
        out.write('%.9g %.9g %.9g\n' % (x, y, z))
    for f in F:
        out.write('3 %d %d %d\n' % f)
