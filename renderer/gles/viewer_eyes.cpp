// SPDX-License-Identifier: MIT
#include "viewer_eyes.h"

#include <algorithm>

#include <GLES3/gl31.h>

#include "vpe/proto/viewing_zone.h"

namespace vpe::renderer::gles {

void ViewerEyes::setUniforms(unsigned program) const {
    glUniform3fv(glGetUniformLocation(program, "uViewer"), 1, viewer.data());
    const auto count =
        static_cast<GLsizei>(std::min<std::size_t>(zone.size(), proto::kMaxViewingZone));
    if (count > 0) {
        glUniform3fv(glGetUniformLocation(program, "uZone"), count, zone.front().data());
    }
    glUniform1i(glGetUniformLocation(program, "uZoneCount"), count);
}

}  // namespace vpe::renderer::gles
