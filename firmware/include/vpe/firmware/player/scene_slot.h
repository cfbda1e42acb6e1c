// SPDX-License-Identifier: MIT
// SceneSlot: a bundle and the renderer made from it, kept together because the renderer was
// built from the bundle's mapped memory. Loading one is all or nothing: a reload builds a new
// slot beside the playing one and swaps only when it is complete.
#pragma once

#include <filesystem>
#include <memory>
#include <string>

#include "vpe/proto/bundle.h"
#include "vpe/proto/input_error.h"
#include "vpe/renderer/gles/gles_frame_renderer.h"

namespace vpe::firmware {

// One line naming the bundle: "scene.vpeb: checksum mismatch …".
class SceneLoadError : public proto::InputError {
public:
    using proto::InputError::InputError;
};

class SceneSlot {
public:
    // The platform's context must be current. `preset`: a name, empty for the first. Throws
    // SceneLoadError.
    static std::unique_ptr<SceneSlot> load(const std::filesystem::path& path,
                                           const std::string& preset);

    const proto::BundleView& view() const { return bundle_.view(); }
    renderer::gles::GlesFrameRenderer& renderer() { return *renderer_; }
    // The preset's index in the bundle, −1 if unknown.
    int presetIndex(const std::string& name) const;

private:
    SceneSlot(proto::BundleFile bundle) : bundle_(std::move(bundle)) {}
    proto::BundleFile bundle_;
    std::unique_ptr<renderer::gles::GlesFrameRenderer> renderer_;
};

}  // namespace vpe::firmware
