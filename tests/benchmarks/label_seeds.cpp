// SPDX-License-Identifier: MIT
// Prints one seed pixel per label of a label image, deepest inside its region, in the form
// `vpe segment --seeds` takes: what a user of the paper's seeded segmentation would click.
//   vpe_label_seeds LABELS.png
#include "support/label_seeds.h"

#include <cstdio>

#include "vpe/segment/label_comparison.h"

#include "tool_errors.h"

int main(int argc, char** argv) {
    if (argc != 2) {
        std::fprintf(stderr, "usage: %s LABELS.png\n", argv[0]);
        return 2;
    }
    return vpe::benchmarks::exitStatusOf([&] {
        const vpe::segment::LabelMap map = vpe::segment::readLabelImage(argv[1]);
        std::printf("%s\n",
                    vpe::testing::seedsArgument(vpe::testing::innermostPixels(map)).c_str());
    });
}
