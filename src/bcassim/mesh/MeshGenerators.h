// Structured tetrahedral meshes of simple solids (boxes, cylinders) for the verification scenes
// and tests: deterministic, conforming, every tet positively oriented. Lengths in metres.
#pragma once
#include "bcassim/Types.h"
#include "bcassim/mesh/TetMesh.h"
#include "bcassim/mesh/TriMesh.h"

namespace bcassim {

// Box [0,sx]x[0,sy]x[0,sz] split into nx*ny*nz hexahedra, each cut into 6 tets around its main
// diagonal (Kuhn split; conforming because every hex uses the same diagonal direction).
// Node (i,j,k) has index i + (nx+1)*(j + (ny+1)*k); the last layer of nodes lies exactly on the
// far faces. size: 3 side lengths, metres. Throws InputError for a non-positive size or count.
TetMesh makeBoxMesh(const Vec3& size, int nx, int ny, int nz);

// Box as above with nx:ny:nz chosen proportional to the sides (near-cubic hexes) so that
// 6*nx*ny*nz is as close to targetTets as such near-cubic grids allow.
TetMesh makeBoxMeshWithTargetTets(const Vec3& size, int targetTets);

// Cylinder of the given radius (m) along +z from z=0 to z=length (m), axis at x=y=0. The cross
// section is a disc of concentric rings of nodes (ring k carrying n1*k nodes, outer ring on the
// circle) triangulated ring by ring, extruded in equal layers; each prism is cut into 3 tets
// with diagonals chosen by node index, which keeps neighbouring prisms conforming. Rings, n1 and
// layers are chosen so that the node count is within a few percent of targetNodes and the tets
// are as well shaped as this construction allows. Throws InputError for non-positive arguments.
TetMesh makeCylinderMesh(double radius, double length, int targetNodes);

// Closed triangle surface of a sphere of `radius` (m) centred at the origin: the icosahedron
// subdivided `levels` times (20 * 4^levels faces), outward counter-clockwise faces.
TriMesh makeIcosphereSurface(double radius, int levels);

}  // namespace bcassim
