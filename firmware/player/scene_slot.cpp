// SPDX-License-Identifier: MIT
#include "vpe/firmware/player/scene_slot.h"

namespace vpe::firmware {

namespace {

// The renderer's errors name the bundle already; others get its name in front.
std::string namingBundle(const std::filesystem::path& bundle, const std::string& message) {
    return message.rfind(bundle.string() + ":", 0) == 0 ? message
                                                        : bundle.string() + ": " + message;
}

}  // namespace

std::unique_ptr<SceneSlot> SceneSlot::load(const std::filesystem::path& path,
                                           const std::string& preset) {
    std::unique_ptr<SceneSlot> slot;
    try {
        slot.reset(new SceneSlot(proto::BundleFile::open(path)));
    } catch (const proto::BundleError& error) {
        throw SceneLoadError(error.what());
    }
    try {
        slot->renderer_ = std::make_unique<renderer::gles::GlesFrameRenderer>(slot->view());
        slot->renderer_->selectPreset(preset);
    } catch (const renderer::gles::GraphicsError& error) {
        throw SceneLoadError(namingBundle(path, error.what()));
    } catch (const std::invalid_argument& error) {
        throw SceneLoadError(namingBundle(path, error.what()));
    }
    return slot;
}

int SceneSlot::presetIndex(const std::string& name) const {
    const auto& presets = view().presets();
    for (std::size_t i = 0; i < presets.size(); ++i) {
        if (presets[i].name == name) {
            return static_cast<int>(i);
        }
    }
    return -1;
}

}  // namespace vpe::firmware
