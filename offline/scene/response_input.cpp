// SPDX-License-Identifier: MIT
// ResponseInput: gammas and measured curves, checked with offline-grade messages.
#include "vpe/scene/response_input.h"

#include <algorithm>
#include <charconv>
#include <cmath>
#include <optional>
#include <string>

#include "vpe/common/input_error.h"
#include "vpe/text/line_reader.h"

namespace vpe::scene {

namespace {

constexpr const char* kChannelNames[3] = {"r", "g", "b"};

std::string formatNumber(double value) {
    std::array<char, 32> buffer{};
    const auto result = std::to_chars(buffer.data(), buffer.data() + buffer.size(), value);
    return std::string(buffer.data(), result.ptr);
}

std::vector<std::string_view> splitCommas(std::string_view text) {
    std::vector<std::string_view> fields;
    while (true) {
        const std::size_t comma = text.find(',');
        fields.push_back(text::trim(text.substr(0, comma)));
        if (comma == std::string_view::npos) {
            return fields;
        }
        text.remove_prefix(comma + 1);
    }
}

// Errors name the line a sample came from when there is one (a file), else the sample.
[[noreturn]] void fail(std::string_view source, const std::vector<int>* lines, std::size_t sample,
                       const std::string& problem) {
    if (lines != nullptr) {
        throw common::InputError(std::filesystem::path(source), (*lines)[sample], problem);
    }
    throw common::InputError(std::string(source) + ": sample " + std::to_string(sample + 1) + ": " +
                             problem);
}

void checkSamples(const std::vector<double>& levels,
                  const std::array<std::vector<double>, 3>& outputs, std::string_view source,
                  const std::vector<int>* lines) {
    const std::size_t n = levels.size();
    if (n < 2) {
        throw common::InputError(std::string(source) + ": " + std::to_string(n) +
                                 (n == 1 ? " sample" : " samples") +
                                 "; a response curve needs at least 2 (levels 0 and 1)");
    }
    for (const auto& channel : outputs) {
        if (channel.size() != n) {
            throw common::InputError(std::string(source) +
                                     ": each channel needs one output per level");
        }
    }
    for (std::size_t k = 0; k < n; ++k) {
        if (!std::isfinite(levels[k]) || levels[k] < 0 || levels[k] > 1) {
            fail(source, lines, k, "level " + formatNumber(levels[k]) + " is outside [0, 1]");
        }
        if (k > 0 && !(levels[k] > levels[k - 1])) {
            fail(source, lines, k,
                 "level " + formatNumber(levels[k]) + " does not increase from the previous " +
                     formatNumber(levels[k - 1]));
        }
        for (int c = 0; c < 3; ++c) {
            const double value = outputs[static_cast<std::size_t>(c)][k];
            if (!std::isfinite(value) || value < 0) {
                fail(source, lines, k,
                     std::string(kChannelNames[c]) + " output " + formatNumber(value) +
                         " is not a finite number ≥ 0");
            }
            const double previous = k > 0 ? outputs[static_cast<std::size_t>(c)][k - 1] : value;
            if (value < previous) {
                fail(source, lines, k,
                     std::string(kChannelNames[c]) + " output " + formatNumber(value) +
                         " is below the previous " + formatNumber(previous) +
                         ": the response must be monotone non-decreasing");
            }
        }
    }
    if (levels.front() != 0) {
        fail(source, lines, 0,
             "the first level is " + formatNumber(levels.front()) +
                 "; the curve must start at level 0");
    }
    if (levels.back() != 1) {
        fail(
            source, lines, n - 1,
            "the last level is " + formatNumber(levels.back()) + "; the curve must end at level 1");
    }
    for (int c = 0; c < 3; ++c) {
        const auto& channel = outputs[static_cast<std::size_t>(c)];
        if (!(channel.back() > channel.front())) {
            throw common::InputError(std::string(source) + ": channel " + kChannelNames[c] +
                                     " is flat (output " + formatNumber(channel.front()) +
                                     " at every level): nothing to invert");
        }
    }
}

ResponseInput makeSampled(std::vector<double> levels, std::array<std::vector<double>, 3> outputs,
                          std::string_view source, const std::vector<int>* lines);

std::optional<std::vector<double>> parseNumberList(std::string_view text) {
    std::vector<double> values;
    for (const std::string_view field : splitCommas(text)) {
        const auto value = text::parseNumber(field);
        if (!value) {
            return std::nullopt;
        }
        values.push_back(*value);
    }
    return values;
}

}  // namespace

ResponseInput ResponseInput::gamma(double exponent) {
    return gamma({exponent, exponent, exponent});
}

ResponseInput ResponseInput::gamma(const std::array<double, 3>& exponents) {
    for (int c = 0; c < 3; ++c) {
        const double g = exponents[static_cast<std::size_t>(c)];
        if (!std::isfinite(g) || !(g > 0)) {
            throw common::InputError(std::string("response: gamma of ") + kChannelNames[c] +
                                     " is " + formatNumber(g) + "; it must be a positive number");
        }
    }
    ResponseInput response;
    response.exponents_ = exponents;
    response.curve_ = proto::ResponseFunction::gamma(exponents);
    return response;
}

ResponseInput ResponseInput::sampled(std::vector<double> levels,
                                     std::array<std::vector<double>, 3> outputs,
                                     std::string_view source) {
    checkSamples(levels, outputs, source, nullptr);
    ResponseInput response;
    // The curve itself, and its inverse, are proto's: one implementation for the offline
    // tools and the device.
    response.curve_ = proto::ResponseFunction::sampled(std::move(levels), std::move(outputs));
    return response;
}

double ResponseInput::output(int channel, double level) const {
    return curve_.output(channel, level);
}

double ResponseInput::level(int channel, double fraction) const {
    return curve_.level(channel, fraction);
}

std::array<double, 3> ResponseInput::output(const std::array<double, 3>& levels) const {
    return {output(0, levels[0]), output(1, levels[1]), output(2, levels[2])};
}

std::array<double, 3> ResponseInput::level(const std::array<double, 3>& fractions) const {
    return {level(0, fractions[0]), level(1, fractions[1]), level(2, fractions[2])};
}

ResponseInput readProjectorResponseCsv(const std::filesystem::path& path) {
    const std::string contents = text::readTextFile(path, "projector response");
    std::vector<double> levels;
    std::array<std::vector<double>, 3> outputs;
    std::vector<int> lines;
    bool first = true;
    for (const text::Line& line : text::splitLines(contents)) {
        if (line.text.empty() || line.text.front() == '#') {
            continue;
        }
        const std::vector<std::string_view> fields = splitCommas(line.text);
        std::array<std::optional<double>, 4> values;
        bool anyNumber = false;
        for (std::size_t i = 0; i < std::min<std::size_t>(fields.size(), 4); ++i) {
            values[i] = text::parseNumber(fields[i]);
            anyNumber = anyNumber || values[i].has_value();
        }
        const bool header = first && !anyNumber;
        first = false;
        if (header) {
            continue;
        }
        if (fields.size() != 4) {
            throw common::InputError(path, line.number,
                                     "expected level,r,g,b (4 numbers), found " +
                                         std::to_string(fields.size()) +
                                         (fields.size() == 1 ? " field" : " fields"));
        }
        constexpr const char* kNames[4] = {"level", "r", "g", "b"};
        for (std::size_t i = 0; i < 4; ++i) {
            if (!values[i]) {
                throw common::InputError(
                    path, line.number,
                    std::string(kNames[i]) + " '" + std::string(fields[i]) + "' is not a number");
            }
        }
        levels.push_back(*values[0]);
        for (std::size_t c = 0; c < 3; ++c) {
            outputs[c].push_back(*values[c + 1]);
        }
        lines.push_back(line.number);
    }
    return makeSampled(std::move(levels), std::move(outputs), path.string(), &lines);
}

namespace {

ResponseInput makeSampled(std::vector<double> levels, std::array<std::vector<double>, 3> outputs,
                          std::string_view source, const std::vector<int>* lines) {
    // Checked here first so that errors carry line numbers; sampled() checks again.
    checkSamples(levels, outputs, source, lines);
    return ResponseInput::sampled(std::move(levels), std::move(outputs), source);
}

}  // namespace

ResponseInput parseProjectorResponse(std::string_view argument) {
    const bool looksNumeric =
        !argument.empty() &&
        argument.find_first_not_of("0123456789.,+-eE \t") == std::string_view::npos;
    if (!looksNumeric) {
        return readProjectorResponseCsv(std::filesystem::path(argument));
    }
    const auto values = parseNumberList(argument);
    if (!values || (values->size() != 1 && values->size() != 3)) {
        throw common::InputError(
            "--response: '" + std::string(argument) +
            "' is neither a gamma (2.2 or r,g,b like 2.2,2.2,2.4) nor a CSV file");
    }
    if (values->size() == 1) {
        return ResponseInput::gamma(values->front());
    }
    return ResponseInput::gamma({(*values)[0], (*values)[1], (*values)[2]});
}

}  // namespace vpe::scene
