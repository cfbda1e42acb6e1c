// SPDX-License-Identifier: MIT
// Projector responses (gamma, sampled CSV): inverses, clamping, flat stretches, and CSV errors
// by line.
#include "vpe/scene/response_input.h"

#include <cmath>
#include <cstring>
#include <string>

#include <gtest/gtest.h>

#include "vpe/common/input_error.h"

#include "offline/scene/scene_test_support.h"
#include "support/test_data.h"

namespace vpe::scene {
namespace {

using namespace test;  // NOLINT: the shared helpers of scene_test_support.h
using testing::TemporaryFolder;

TEST(ResponseInput, GammaInverseUndoesTheResponse) {
    const ResponseInput response = ResponseInput::gamma({2.2, 2.4, 1.8});
    for (int c = 0; c < 3; ++c) {
        for (int i = 0; i <= 100; ++i) {
            const double x = i / 100.0;
            EXPECT_NEAR(response.level(c, response.output(c, x)), x, 1e-12);
        }
    }
    EXPECT_NEAR(response.output(0, 0.5), std::pow(0.5, 2.2), 1e-15);
    EXPECT_EQ(response.level(0, -0.5), 0.0);
    EXPECT_EQ(response.level(0, 1.5), 1.0);
    EXPECT_EQ(response.level(0, std::nan("")), 0.0);
    EXPECT_EQ(response.output(1, 2.0), 1.0);
}

TEST(ResponseInput, SampledInverseUndoesTheResponseAndClamps) {
    // In cd/m², with a black level: normalized per channel.
    const ResponseInput response = ResponseInput::sampled(
        {0, 0.25, 0.5, 0.75, 1}, {{{2, 10, 40, 90, 200}, {1, 5, 20, 45, 100}, {0, 1, 2, 3, 4}}});
    EXPECT_NEAR(response.output(0, 1), 1.0, 1e-15);
    EXPECT_NEAR(response.output(0, 0), 0.01, 1e-15);
    EXPECT_NEAR(response.output(2, 0.625), 0.625, 1e-15);
    for (int c = 0; c < 3; ++c) {
        for (int i = 0; i <= 200; ++i) {
            const double x = i / 200.0;
            EXPECT_NEAR(response.level(c, response.output(c, x)), x, 1e-12) << c << " " << x;
        }
    }
    EXPECT_EQ(response.level(0, 0.005), 0.0);  // below the black level
    EXPECT_EQ(response.level(0, 2.0), 1.0);
    const auto rgb = response.level(response.output({0.3, 0.6, 0.9}));
    EXPECT_NEAR(rgb[0], 0.3, 1e-12);
    EXPECT_NEAR(rgb[1], 0.6, 1e-12);
    EXPECT_NEAR(rgb[2], 0.9, 1e-12);
}

TEST(ResponseInput, FlatStretchesInvertToTheirLowestLevel) {
    const ResponseInput response = ResponseInput::sampled(
        {0, 0.5, 0.8, 1}, {{{0, 0.5, 1, 1}, {0, 0.5, 0.5, 1}, {0, 0.5, 0.5, 1}}});
    EXPECT_DOUBLE_EQ(response.level(0, 1.0), 0.8);  // saturates before level 1
    EXPECT_DOUBLE_EQ(response.level(1, 0.5), 0.5);
    EXPECT_DOUBLE_EQ(response.level(1, 0.75), 0.9);
}

TEST(ResponseInput, ReadsCsvWithHeaderAndComments) {
    TemporaryFolder folder;
    writeFile(folder / "response.csv",
              "\xEF\xBB\xBFlevel,r,g,b\r\n# measured 2024\r\n0, 0.01, 0.01, 0.02\r\n\r\n"
              "0.5,0.2,0.21,0.22\r\n1,1,1,1\r\n");
    const ResponseInput response = readProjectorResponseCsv(folder / "response.csv");
    EXPECT_FALSE(response.isGamma());
    EXPECT_NEAR(response.output(0, 0.25), 0.105, 1e-12);
    EXPECT_NEAR(response.level(2, 0.22), 0.5, 1e-12);
    const ResponseInput same = parseProjectorResponse((folder / "response.csv").string());
    EXPECT_NEAR(same.output(1, 0.75), 0.605, 1e-12);
}

TEST(ResponseInput, CsvErrorsNameTheLine) {
    TemporaryFolder folder;
    const auto refuse = [&](const std::string& text, const std::string& fragment) {
        SCOPED_TRACE(text);
        writeFile(folder / "r.csv", text);
        EXPECT_INPUT_ERROR(readProjectorResponseCsv(folder / "r.csv"), "r.csv" + fragment);
    };
    refuse("level,r,g,b\n0,0,0,0\n0.5,0.6,0.4,0.4\n0.7,0.5,0.6,0.6\n1,1,1,1\n",
           ":4: r output 0.5 is below the previous 0.6: the response must be monotone "
           "non-decreasing");
    refuse("0,0,0,0\n0.5,0.1,0.1,0.1\n0.5,0.2,0.2,0.2\n1,1,1,1\n",
           ":3: level 0.5 does not increase from the previous 0.5");
    refuse("0,0,0,0\n", ": 1 sample; a response curve needs at least 2 (levels 0 and 1)");
    refuse("# nothing\n", ": 0 samples; a response curve needs at least 2");
    refuse("0,0,0,0\n0.5,0.1,zero,0.1\n1,1,1,1\n", ":2: g 'zero' is not a number");
    refuse("0,0,0,0\n0.5,0.1,0.1\n1,1,1,1\n", ":2: expected level,r,g,b (4 numbers), found 3");
    refuse("0,0,0,0\n0.5;0.1;0.1;0.1\n", ":2: expected level,r,g,b (4 numbers), found 1 field");
    refuse("0.1,0,0,0\n1,1,1,1\n", ":1: the first level is 0.1; the curve must start at level 0");
    refuse("0,0,0,0\n0.9,1,1,1\n", ":2: the last level is 0.9; the curve must end at level 1");
    refuse("0,0,0,0\n1,1,1,1.5\n1.5,1,1,2\n", ":3: level 1.5 is outside [0, 1]");
    refuse("0,0,0,-1\n1,1,1,1\n", ":1: b output -1 is not a finite number ≥ 0");
    refuse("0,0,0.3,0\n1,1,0.3,1\n", ": channel g is flat (output 0.3 at every level)");
    refuse("0,0,0,0\n1,1,nan,1\n", ":2: g 'nan' is not a number");
    EXPECT_INPUT_ERROR(readProjectorResponseCsv(folder / "absent.csv"),
                       "absent.csv: cannot open projector response");
}

TEST(ResponseInput, ParsesGammaArguments) {
    EXPECT_TRUE(parseProjectorResponse("2.2").isGamma());
    EXPECT_DOUBLE_EQ(parseProjectorResponse("2.2").exponents()[2], 2.2);
    EXPECT_DOUBLE_EQ(parseProjectorResponse("2.2, 2.3,2.4").exponents()[1], 2.3);
    EXPECT_INPUT_ERROR(parseProjectorResponse("2.2,2.2"), "--response: '2.2,2.2' is neither");
    EXPECT_INPUT_ERROR(parseProjectorResponse("0"), "response: gamma of r is 0");
    EXPECT_INPUT_ERROR(parseProjectorResponse("-1,2,2"), "gamma of r is -1");
    EXPECT_INPUT_ERROR(ResponseInput::gamma(std::nan("")), "gamma of r is nan");
}

}  // namespace
}  // namespace vpe::scene
