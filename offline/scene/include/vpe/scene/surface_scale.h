// SPDX-License-Identifier: MIT
// SurfaceScale: how long the texture's axes are on the screen object — per triangle, the
// surface length of a unit step in u and in v (|∂p/∂u|, |∂p/∂v| from its positions and uvs)
// and its area — and whether u wraps around it. From these: the texture size at which a texel
// has a given physical size (`vpe quilt --size auto`), and how far texels are from square on
// the surface at any size (the stretch).
#pragma once

#include <cstddef>
#include <vector>

#include "vpe/scene/screen_mesh.h"

namespace vpe::scene {

struct TriangleScale {
    double area = 0;     // m²
    double lengthU = 0;  // |∂p/∂u|: metres per unit of u
    double lengthV = 0;  // |∂p/∂v|: metres per unit of v
    float u = 0, v = 0;  // the triangle's uv centroid (where it is, for reports)
};

struct SurfaceScale {
    std::vector<TriangleScale> triangles;  // those whose uvs span an area
    double area = 0;                       // m², of those triangles
    std::size_t flatUvTriangles = 0;       // triangles whose uvs span no area: left out
    // u wraps: the mesh has a seam where vertices at u = 0 and u = 1 share a position (and v),
    // so the texture's left and right edges meet on the surface and must tile.
    bool wrapsU = false;
    std::size_t seamVertexPairs = 0;
};

// Throws InputError naming `source` when no triangle's uvs span an area.
SurfaceScale measureSurfaceScale(const ScreenMesh& mesh, const char* source = "mesh");

// A texel's two surface lengths, (lengthU / width, lengthV / height), over the mesh.
struct TexelStretch {
    // max/min of the two lengths: worst over the triangles, and area-weighted statistics.
    double worst = 1;
    float worstU = 0, worstV = 0;  // where the worst is (uv centroid)
    double mean = 1, median = 1, p95 = 1;
    // Area-weighted geometric means of the texel's length along u and v, millimetres.
    double texelUMm = 0, texelVMm = 0;
};

TexelStretch measureTexelStretch(const SurfaceScale& scale, int width, int height);

struct AutoTextureSize {
    int width = 0;
    int height = 0;
};

// The size at which a texel is `texelMm` long on the surface along u and along v, as
// area-weighted geometric means (so a streak as wide on the screen object as on the captured
// one, and texels as square as one size for the whole mesh can make them). Throws InputError
// when a side would exceed `maxSide` (naming the size and the texel) or fall below 8.
AutoTextureSize chooseTextureSize(const SurfaceScale& scale, double texelMm, int maxSide);

}  // namespace vpe::scene
