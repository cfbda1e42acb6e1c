// SPDX-License-Identifier: MIT
// Prints one seed pixel per label of a label image, deepest inside its region, in the form
// `vpe segment --seeds` takes: what a user of the paper's seeded segmentation would click.
//   vpe_label_seeds LABELS.png
#include "support/label_seeds.h"

#include <cstdio>
#include <exception>

#include "vpe/common/input_error.h"
#include "vpe/segment/label_comparison.h"

int main(int argc, char** argv) {
    if (argc != 2) {
        std::fprintf(stderr, "usage: %s LABELS.png\n", argv[0]);
        return 2;
    }
    try {
        const vpe::segment::LabelMap map = vpe::segment::readLabelImage(argv[1]);
        std::printf("%s\n",
                    vpe::testing::seedsArgument(vpe::testing::innermostPixels(map)).c_str());
    } catch (const vpe::common::InputError& error) {
        std::fprintf(stderr, "%s\n", error.what());
        return 2;
    } catch (const std::exception& error) {
        std::fprintf(stderr, "internal error: %s\n", error.what());
        return 1;
    }
    return 0;
}
