// SPDX-License-Identifier: MIT
// Screen mesh loading (assimp), validation and OBJ writing.
#include "vpe/scene/screen_mesh.h"

#include <algorithm>
#include <array>
#include <charconv>
#include <cmath>
#include <fstream>
#include <limits>
#include <string>
#include <utility>
#include <vector>

#include <assimp/Importer.hpp>
#include <assimp/postprocess.h>
#include <assimp/scene.h>

#include "vpe/common/input_error.h"
#include "vpe/proto/atomic_file.h"

namespace vpe::scene {

namespace {

// assimp's messages can span lines; ours are one line.
std::string oneLine(std::string text) {
    std::replace_if(
        text.begin(), text.end(), [](char c) { return c == '\n' || c == '\r'; }, ' ');
    while (!text.empty() && text.back() == ' ') {
        text.pop_back();
    }
    return text;
}

std::string lowercase(std::string text) {
    std::transform(text.begin(), text.end(), text.begin(),
                   [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
    return text;
}

std::string formatNumber(double value) {
    std::array<char, 32> buffer{};
    const auto result = std::to_chars(buffer.data(), buffer.data() + buffer.size(), value);
    return std::string(buffer.data(), result.ptr);
}

bool finite(const Vec3f& v) {
    return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z);
}

std::array<double, 3> toDouble(const Vec3f& v) {
    return {static_cast<double>(v.x), static_cast<double>(v.y), static_cast<double>(v.z)};
}

// Twice the triangle's area times its unit normal.
std::array<double, 3> areaVector(const ScreenMesh& mesh, std::size_t triangle) {
    const auto a = toDouble(mesh.positions[mesh.indices[3 * triangle]]);
    const auto b = toDouble(mesh.positions[mesh.indices[3 * triangle + 1]]);
    const auto c = toDouble(mesh.positions[mesh.indices[3 * triangle + 2]]);
    const std::array<double, 3> e1{b[0] - a[0], b[1] - a[1], b[2] - a[2]};
    const std::array<double, 3> e2{c[0] - a[0], c[1] - a[1], c[2] - a[2]};
    return {e1[1] * e2[2] - e1[2] * e2[1], e1[2] * e2[0] - e1[0] * e2[2],
            e1[0] * e2[1] - e1[1] * e2[0]};
}

double length(const std::array<double, 3>& v) {
    return std::sqrt(v[0] * v[0] + v[1] * v[1] + v[2] * v[2]);
}

// Drops triangles of (numerically) zero area. "Zero" is relative to the mesh's size, so a
// model in millimetres and one in metres lose the same triangles.
void dropDegenerateTriangles(ScreenMesh& mesh, const std::filesystem::path& source) {
    Vec3f low = mesh.positions.front(), high = mesh.positions.front();
    for (const Vec3f& p : mesh.positions) {
        low = {std::min(low.x, p.x), std::min(low.y, p.y), std::min(low.z, p.z)};
        high = {std::max(high.x, p.x), std::max(high.y, p.y), std::max(high.z, p.z)};
    }
    const double diagonal = length({static_cast<double>(high.x) - static_cast<double>(low.x),
                                    static_cast<double>(high.y) - static_cast<double>(low.y),
                                    static_cast<double>(high.z) - static_cast<double>(low.z)});
    const double minimum = 1e-12 * diagonal * diagonal;
    const std::size_t triangles = mesh.triangleCount();
    std::vector<std::uint32_t> kept;
    kept.reserve(mesh.indices.size());
    for (std::size_t t = 0; t < triangles; ++t) {
        if (length(areaVector(mesh, t)) > minimum) {
            kept.insert(kept.end(), mesh.indices.begin() + static_cast<std::ptrdiff_t>(3 * t),
                        mesh.indices.begin() + static_cast<std::ptrdiff_t>(3 * t + 3));
        }
    }
    if (kept.empty()) {
        throw common::InputError(source, "all " + std::to_string(triangles) +
                                             " triangles are degenerate (zero area): nothing to "
                                             "project on");
    }
    mesh.indices = std::move(kept);
}

// Removes vertices no triangle uses (left by dropped triangles, or points in the file).
void dropUnreferencedVertices(ScreenMesh& mesh) {
    constexpr std::uint32_t kUnused = std::numeric_limits<std::uint32_t>::max();
    std::vector<std::uint32_t> remap(mesh.vertexCount(), kUnused);
    for (const std::uint32_t index : mesh.indices) {
        remap[index] = 0;
    }
    std::uint32_t next = 0;
    for (std::size_t i = 0; i < remap.size(); ++i) {
        if (remap[i] != kUnused) {
            mesh.positions[next] = mesh.positions[i];
            mesh.normals[next] = mesh.normals[i];
            mesh.uvs[next] = mesh.uvs[i];
            remap[i] = next++;
        }
    }
    if (next == mesh.vertexCount()) {
        return;
    }
    mesh.positions.resize(next);
    mesh.normals.resize(next);
    mesh.uvs.resize(next);
    for (std::uint32_t& index : mesh.indices) {
        index = remap[index];
    }
}

// Unit normals; a vertex whose normal is missing, zero or not finite gets the area-weighted
// normal of its triangles.
void repairNormals(ScreenMesh& mesh, const std::filesystem::path& source) {
    std::vector<std::array<double, 3>> fallback;
    for (std::size_t i = 0; i < mesh.vertexCount(); ++i) {
        const Vec3f n = mesh.normals[i];
        const double norm = finite(n) ? length(toDouble(n)) : 0.0;
        if (norm > 1e-12) {
            mesh.normals[i] = {static_cast<float>(static_cast<double>(n.x) / norm),
                               static_cast<float>(static_cast<double>(n.y) / norm),
                               static_cast<float>(static_cast<double>(n.z) / norm)};
            continue;
        }
        if (fallback.empty()) {
            fallback.assign(mesh.vertexCount(), {0, 0, 0});
            for (std::size_t t = 0; t < mesh.triangleCount(); ++t) {
                const auto area = areaVector(mesh, t);
                for (int corner = 0; corner < 3; ++corner) {
                    auto& sum = fallback[mesh.indices[3 * t + static_cast<std::size_t>(corner)]];
                    sum = {sum[0] + area[0], sum[1] + area[1], sum[2] + area[2]};
                }
            }
        }
        const double fallbackNorm = length(fallback[i]);
        if (!(fallbackNorm > 0)) {
            throw common::InputError(
                source,
                "vertex " + std::to_string(i) + " has no usable normal (its triangles cancel out)");
        }
        mesh.normals[i] = {static_cast<float>(fallback[i][0] / fallbackNorm),
                           static_cast<float>(fallback[i][1] / fallbackNorm),
                           static_cast<float>(fallback[i][2] / fallbackNorm)};
    }
}

}  // namespace

void requireIndexableVertexCount(std::uint64_t count, const std::filesystem::path& source) {
    // 2³² − 1 at most: index 0xFFFFFFFF is GL's primitive-restart index (and our marker).
    if (count > std::numeric_limits<std::uint32_t>::max()) {
        throw common::InputError(source,
                                 std::to_string(count) +
                                     " vertices: more than 32-bit indices can address (at most "
                                     "4294967295); split or decimate the mesh");
    }
}

void validateScreenMesh(ScreenMesh& mesh, const std::filesystem::path& source) {
    if (mesh.indices.empty()) {
        throw common::InputError(source,
                                 "no triangles: a screen mesh needs faces, not only points or "
                                 "lines");
    }
    if (mesh.indices.size() % 3 != 0) {
        throw common::InputError(source, "index count " + std::to_string(mesh.indices.size()) +
                                             " is not a multiple of 3");
    }
    requireIndexableVertexCount(mesh.positions.size(), source);
    if (mesh.normals.size() != mesh.positions.size() || mesh.uvs.size() != mesh.positions.size()) {
        throw common::InputError(source, "normals or texture coordinates do not match the " +
                                             std::to_string(mesh.positions.size()) + " positions");
    }
    for (std::size_t i = 0; i < mesh.indices.size(); ++i) {
        if (mesh.indices[i] >= mesh.positions.size()) {
            throw common::InputError(source, "triangle " + std::to_string(i / 3) + " uses vertex " +
                                                 std::to_string(mesh.indices[i]) + " of " +
                                                 std::to_string(mesh.positions.size()));
        }
    }
    for (std::size_t i = 0; i < mesh.positions.size(); ++i) {
        const Vec3f& p = mesh.positions[i];
        if (!finite(p)) {
            throw common::InputError(source, "vertex " + std::to_string(i) +
                                                 " has a position that is "
                                                 "not a finite number (" +
                                                 formatNumber(static_cast<double>(p.x)) + ", " +
                                                 formatNumber(static_cast<double>(p.y)) + ", " +
                                                 formatNumber(static_cast<double>(p.z)) + ")");
        }
    }
    for (std::size_t i = 0; i < mesh.uvs.size(); ++i) {
        Vec2f& uv = mesh.uvs[i];
        const auto inside = [](float x) { return x >= -kUvTolerance && x <= 1 + kUvTolerance; };
        if (!inside(uv.x) || !inside(uv.y)) {  // also catches NaN
            throw common::InputError(source,
                                     "vertex " + std::to_string(i) + " has texture coordinates (" +
                                         formatNumber(static_cast<double>(uv.x)) + ", " +
                                         formatNumber(static_cast<double>(uv.y)) +
                                         ") outside [0, 1]; vpe does not wrap or tile them");
        }
        uv = {std::clamp(uv.x, 0.0f, 1.0f), std::clamp(uv.y, 0.0f, 1.0f)};
    }
    dropDegenerateTriangles(mesh, source);
    dropUnreferencedVertices(mesh);
    repairNormals(mesh, source);
}

ScreenMesh loadScreenMesh(const std::filesystem::path& path, const ScreenMeshLoadOptions& options) {
    const std::string extension = lowercase(path.extension().string());
    if (extension != ".obj" && extension != ".ply") {
        throw common::InputError(path, "unsupported mesh format '" + path.extension().string() +
                                           "' (vpe reads .obj and .ply)");
    }
    std::error_code error;
    if (!std::filesystem::is_regular_file(path, error)) {
        throw common::InputError(path, std::filesystem::exists(path, error)
                                           ? "cannot open mesh: not a regular file"
                                           : "cannot open mesh: no such file");
    }
    if (!(options.metresPerUnit > 0) || !std::isfinite(options.metresPerUnit)) {
        throw common::InputError(path, "mesh unit scale must be a positive number, not " +
                                           formatNumber(options.metresPerUnit));
    }

    // The importer logs only through assimp's DefaultLogger, which stays the silent
    // NullLogger unless someone creates it: nothing here writes to stdout or stderr.
    // (aiProcess_PreTransformVertices is not used: it refuses a scene of points outright,
    // which deserves the clearer "no triangles"; node transforms are applied below.)
    Assimp::Importer importer;
    const aiScene* scene = importer.ReadFile(path.string(), 0);
    const auto parseFailure = [&] {
        const std::string reason = oneLine(importer.GetErrorString());
        return common::InputError(path,
                                  "cannot parse mesh" + (reason.empty() ? "" : ": " + reason));
    };
    if (scene == nullptr || scene->mRootNode == nullptr) {
        throw parseFailure();
    }
    // Non-finite numbers are looked for before post-processing, which could merge a NaN
    // vertex into another (NaN compares equal to nothing) and hide it.
    for (unsigned m = 0; m < scene->mNumMeshes; ++m) {
        const aiMesh& part = *scene->mMeshes[m];
        for (unsigned i = 0; i < part.mNumVertices; ++i) {
            const aiVector3D& p = part.mVertices[i];
            if (!std::isfinite(p.x) || !std::isfinite(p.y) || !std::isfinite(p.z)) {
                throw common::InputError(path,
                                         "a vertex has a position that is not a finite number (" +
                                             formatNumber(static_cast<double>(p.x)) + ", " +
                                             formatNumber(static_cast<double>(p.y)) + ", " +
                                             formatNumber(static_cast<double>(p.z)) + ")");
            }
            if (part.HasTextureCoords(0)) {
                const aiVector3D& uv = part.mTextureCoords[0][i];
                if (!std::isfinite(uv.x) || !std::isfinite(uv.y)) {
                    throw common::InputError(path,
                                             "a vertex has texture coordinates that are not "
                                             "finite numbers (" +
                                                 formatNumber(static_cast<double>(uv.x)) + ", " +
                                                 formatNumber(static_cast<double>(uv.y)) + ")");
                }
            }
        }
    }
    scene = importer.ApplyPostProcessing(aiProcess_Triangulate | aiProcess_JoinIdenticalVertices |
                                         aiProcess_GenSmoothNormals);
    if (scene == nullptr || scene->mRootNode == nullptr) {
        throw parseFailure();
    }

    ScreenMesh mesh;
    std::uint64_t vertices = 0;
    const auto addMesh = [&](const aiMesh& part, const aiMatrix4x4& transform) {
        const bool hasTriangles = std::any_of(part.mFaces, part.mFaces + part.mNumFaces,
                                              [](const aiFace& f) { return f.mNumIndices == 3; });
        if (!hasTriangles) {
            return;  // points or lines: nothing to project on
        }
        if (!part.HasTextureCoords(0) || part.mNumUVComponents[0] < 2) {
            throw common::InputError(path,
                                     "no texture coordinates: a screen mesh needs UVs (vt in OBJ, "
                                     "s/t or u/v in PLY) to carry the projected texture");
        }
        vertices += part.mNumVertices;
        requireIndexableVertexCount(vertices, path);
        // OBJ and PLY scenes have identity transforms; skipping them keeps values bit exact.
        const bool identity = transform.IsIdentity();
        const aiMatrix3x3 normalTransform = aiMatrix3x3(transform).Inverse().Transpose();
        const bool mirrored = aiMatrix3x3(transform).Determinant() < 0;
        const auto base = static_cast<std::uint32_t>(mesh.positions.size());
        const auto scale = options.metresPerUnit;
        for (unsigned i = 0; i < part.mNumVertices; ++i) {
            const aiVector3D p = identity ? part.mVertices[i] : transform * part.mVertices[i];
            mesh.positions.push_back({static_cast<float>(static_cast<double>(p.x) * scale),
                                      static_cast<float>(static_cast<double>(p.y) * scale),
                                      static_cast<float>(static_cast<double>(p.z) * scale)});
            const aiVector3D n = !part.HasNormals() ? aiVector3D(0, 0, 0)
                                 : identity         ? part.mNormals[i]
                                                    : normalTransform * part.mNormals[i];
            mesh.normals.push_back({n.x, n.y, n.z});  // renormalized by validateScreenMesh
            const aiVector3D& uv = part.mTextureCoords[0][i];
            mesh.uvs.push_back({uv.x, uv.y});
        }
        for (unsigned f = 0; f < part.mNumFaces; ++f) {
            const aiFace& face = part.mFaces[f];
            if (face.mNumIndices != 3) {
                continue;
            }
            mesh.indices.push_back(base + face.mIndices[0]);
            mesh.indices.push_back(base + face.mIndices[mirrored ? 2 : 1]);
            mesh.indices.push_back(base + face.mIndices[mirrored ? 1 : 2]);
        }
    };
    // Depth first through the node tree, each mesh placed by its node's transform.
    std::vector<std::pair<const aiNode*, aiMatrix4x4>> pending{
        {scene->mRootNode, scene->mRootNode->mTransformation}};
    while (!pending.empty()) {
        const auto [node, transform] = pending.back();
        pending.pop_back();
        for (unsigned m = 0; m < node->mNumMeshes; ++m) {
            addMesh(*scene->mMeshes[node->mMeshes[m]], transform);
        }
        for (unsigned c = node->mNumChildren; c-- > 0;) {
            pending.emplace_back(node->mChildren[c],
                                 transform * node->mChildren[c]->mTransformation);
        }
    }
    validateScreenMesh(mesh, path);
    return mesh;
}

void writeScreenMeshObj(const ScreenMesh& mesh, const std::filesystem::path& path) {
    proto::AtomicFile output(path);
    {
        std::ofstream stream(output.temporaryPath(), std::ios::binary);
        std::array<char, 128> line{};
        const auto write = [&](const char* tag, std::initializer_list<float> values) {
            char* end = std::copy(tag, tag + std::char_traits<char>::length(tag), line.data());
            for (const float value : values) {
                *end++ = ' ';
                end = std::to_chars(end, line.data() + line.size(), value).ptr;
            }
            *end++ = '\n';
            stream.write(line.data(), end - line.data());
        };
        stream << "# vpe screen mesh: " << mesh.vertexCount() << " vertices, "
               << mesh.triangleCount() << " triangles, metres\n";
        for (const Vec3f& p : mesh.positions) {
            write("v", {p.x, p.y, p.z});
        }
        for (const Vec2f& uv : mesh.uvs) {
            write("vt", {uv.x, uv.y});
        }
        for (const Vec3f& n : mesh.normals) {
            write("vn", {n.x, n.y, n.z});
        }
        for (std::size_t t = 0; t < mesh.triangleCount(); ++t) {
            stream << 'f';
            for (std::size_t k = 0; k < 3; ++k) {
                const std::uint64_t index = std::uint64_t{mesh.indices[3 * t + k]} + 1;
                stream << ' ' << index << '/' << index << '/' << index;
            }
            stream << '\n';
        }
        stream.close();
        if (!stream) {
            throw common::InputError(path, "cannot write mesh");
        }
    }
    output.commit();
}

}  // namespace vpe::scene
