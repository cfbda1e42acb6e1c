// SPDX-License-Identifier: MIT
// libFuzzer target: arbitrary bytes as a device bundle, through the same validation the
// device runs on a mapped file. Either they are refused with one BundleError line naming the
// file, or every span the reader returns lies inside the bytes and agrees with its declared
// dimensions — the renderer uploads them without further checks. Anything else crashes.
//
// The checksum pass is skipped: with it, nearly every mutation would stop at the checksum and
// the structural checks behind it — the ones that stand between a bad file and an
// out-of-bounds read — would go unexplored.
#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <new>
#include <string_view>

#include "vpe/proto/bundle.h"

namespace {

constexpr std::string_view kName = "fuzz.vpeb";

// Copies the input to 64-byte aligned memory, as a mapping is.
class AlignedCopy {
public:
    AlignedCopy(const std::uint8_t* data, std::size_t size)
        : size_(size),
          bytes_(static_cast<std::byte*>(::operator new (size + 1, std::align_val_t{64}))) {
        if (size > 0) {
            std::memcpy(bytes_, data, size);
        }
    }
    ~AlignedCopy() { ::operator delete (bytes_, std::align_val_t{64}); }
    AlignedCopy(const AlignedCopy&) = delete;
    AlignedCopy& operator=(const AlignedCopy&) = delete;
    std::span<const std::byte> span() const { return {bytes_, size_}; }

private:
    std::size_t size_;
    std::byte* bytes_;
};

void require(bool condition) {
    if (!condition) {
        std::abort();
    }
}

template <typename T>
void requireInside(std::span<const T> span, std::span<const std::byte> bytes) {
    if (span.empty()) {
        return;
    }
    const auto* begin = reinterpret_cast<const std::byte*>(span.data());
    require(begin >= bytes.data() && begin + span.size_bytes() <= bytes.data() + bytes.size());
    require(reinterpret_cast<std::uintptr_t>(begin) % alignof(T) == 0);
    // Touch both ends, so that ASan checks the bounds too.
    volatile T first = span.front();
    volatile T last = span.back();
    (void)first;
    (void)last;
}

void requireLayers(const vpe::proto::HalfLayers& layers, int width, int height,
                   std::span<const std::byte> bytes) {
    require(layers.width == width && layers.height == height && layers.layers > 0);
    require(layers.halves.size() == static_cast<std::size_t>(layers.layers) *
                                        static_cast<std::size_t>(width) *
                                        static_cast<std::size_t>(height) * 4);
    requireInside(layers.halves, bytes);
}

void requireMap(const vpe::proto::CoefficientMapView& map, const vpe::proto::BundleView& view) {
    const auto c = static_cast<std::size_t>(view.model().coefficientsPerTexel());
    if (map.encoding == vpe::proto::CoefficientEncoding::kFull) {
        require(static_cast<std::size_t>(map.layers.layers) == (c + 3) / 4);
    } else {
        require(map.rank >= 1 && static_cast<std::size_t>(map.rank) <= c);
        require(map.layers.layers == (map.rank + 3) / 4);
        require(map.mean.size() == c && map.basis.size() == c * static_cast<std::size_t>(map.rank));
        requireInside(map.mean, view.bytes());
        requireInside(map.basis, view.bytes());
    }
    requireLayers(map.layers, view.textureWidth(), view.textureHeight(), view.bytes());
}

// What the renderer relies on once a bundle is accepted.
void requireUsable(const vpe::proto::BundleView& view) {
    const vpe::proto::MeshView& mesh = view.mesh();
    const std::size_t vertices = mesh.vertexCount();
    require(vertices > 0 && mesh.positions.size() == 3 * vertices);
    require(mesh.normals.size() == 3 * vertices && mesh.uvs.size() == 2 * vertices);
    require(mesh.indices.size() % 3 == 0 && !mesh.indices.empty());
    for (std::uint32_t index : mesh.indices) {
        require(index < vertices);
    }
    requireInside(mesh.positions, view.bytes());
    requireInside(mesh.normals, view.bytes());
    requireInside(mesh.uvs, view.bytes());
    requireInside(mesh.indices, view.bytes());
    require(view.textureWidth() >= 1 && view.textureWidth() <= 4096);
    require(view.textureHeight() >= 1 && view.textureHeight() <= 4096);
    require(!view.regions().empty());
    for (const vpe::proto::RegionView& region : view.regions()) {
        requireMap(region.coefficients, view);
    }
    if (view.composed()) {
        requireMap(*view.composed(), view);
    }
    const std::size_t texels = static_cast<std::size_t>(view.textureWidth()) *
                               static_cast<std::size_t>(view.textureHeight());
    for (const vpe::proto::WeightPresetView& preset : view.presets()) {
        require(static_cast<std::size_t>(preset.layers) == view.regions().size());
        const std::size_t values = static_cast<std::size_t>(preset.layers) * texels;
        if (preset.encoding == vpe::proto::AlphaEncoding::kUnorm8) {
            require(preset.unorm8.size() == values && preset.halves.empty());
            requireInside(preset.unorm8, view.bytes());
        } else {
            require(preset.halves.size() == values && preset.unorm8.empty());
            requireInside(preset.halves, view.bytes());
        }
    }
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    const AlignedCopy copy(data, size);
    try {
        const vpe::proto::BundleView view = vpe::proto::BundleView::parse(
            copy.span(), std::string(kName), {.verifyChecksum = false});
        requireUsable(view);
    } catch (const vpe::proto::BundleError& error) {
        const std::string_view message = error.what();
        require(message.starts_with(std::string(kName) + ": ") &&
                message.size() > kName.size() + 2);
        require(message.find('\n') == std::string_view::npos);
    }
    return 0;
}
