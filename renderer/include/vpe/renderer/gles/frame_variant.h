// SPDX-License-Identifier: MIT
// FrameVariant: which of its frame programs GlesFrameRenderer draws with (the frame shader of
// each can be read back, for counting its operations).
#pragma once

namespace vpe::renderer::gles {

// How a frame finds its material. (With live weights, the regions' materials are kept apart
// and the preset's blend of them is composed in projector space when the weights change, not
// every frame: a frame reads one composed material either way.)
enum class FrameVariant {
    kStatic,  // one composed material
    kFade,    // two composed materials mixed: a preset change cross-fading
};
const char* frameVariantName(FrameVariant variant);  // "static", "fade"

}  // namespace vpe::renderer::gles
