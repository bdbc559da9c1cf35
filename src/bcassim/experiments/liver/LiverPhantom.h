// A built-in liver-shaped phantom for runs without the CT data: a tapered, flattened sphere
// (larger right lobe, thin left lobe) with a falciform attachment (label 2) and an
// anterior-inferior ridge (label 3) labelled on its edges like the annotated livers. Metres.
#pragma once
#include "bcassim/ligaments/EsegLabels.h"
#include "bcassim/mesh/TriMesh.h"

namespace bcassim {

struct LiverPhantom {
  TriMesh surface;      // closed, outward; x lateral (right lobe +x), y anterior, z superior
  LabelledEdges edges;  // .eseg order and labels 1 (background), 2 (falciform), 3 (ridge)
};

// About 0.20 x 0.15 x 0.11 m, 2,562 vertices.
LiverPhantom makeLiverPhantom();

}  // namespace bcassim
