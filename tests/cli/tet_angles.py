"""Dihedral angles of tetrahedra from numpy alone, for the tests and benchmarks
that check vdmesh's and TetGen's figures independently of our C++ code."""
import numpy as np


def dihedral_angles(points, tets):
    """The six dihedral angles (degrees) of every tetrahedron, shape (6, n):
    pi minus the angle between the outward normals of the two faces at an edge."""
    corners = [points[tets[:, k]] for k in range(4)]
    normals = []
    for k in range(4):
        f = [corners[j] for j in range(4) if j != k]
        n = np.cross(f[1] - f[0], f[2] - f[0])
        n *= -np.sign(np.einsum("ij,ij->i", n, corners[k] - f[0]))[:, None]
        normals.append(n / np.linalg.norm(n, axis=1)[:, None])
    return np.array([180.0 - np.degrees(np.arccos(np.clip(np.einsum("ij,ij->i", normals[k], normals[l]), -1, 1)))
                     for k in range(4) for l in range(k + 1, 4)])
