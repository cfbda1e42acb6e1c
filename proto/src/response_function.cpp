// SPDX-License-Identifier: MIT
// ResponseFunction: gamma or sampled curve, and its clamped inverse.
#include "vpe/proto/response_function.h"

#include <algorithm>
#include <cmath>
#include <iterator>
#include <stdexcept>
#include <string>
#include <utility>

#include "vpe/proto/half_float.h"

namespace vpe::proto {

namespace {

const char* channelName(std::size_t c) {
    static const char* const kNames[] = {"red", "green", "blue"};
    return kNames[c];
}

}  // namespace

ResponseFunction ResponseFunction::gamma(double exponent) {
    return gamma({exponent, exponent, exponent});
}

ResponseFunction ResponseFunction::gamma(const std::array<double, 3>& exponents) {
    for (std::size_t c = 0; c < 3; ++c) {
        if (!(exponents[c] > 0) || !std::isfinite(exponents[c])) {
            throw std::invalid_argument(std::string("response: gamma of ") + channelName(c) +
                                        " must be a positive number");
        }
    }
    ResponseFunction response;
    response.exponents_ = exponents;
    return response;
}

ResponseFunction ResponseFunction::sampled(std::vector<double> levels,
                                           std::array<std::vector<double>, 3> outputs) {
    return sampled(std::array<std::vector<double>, 3>{levels, levels, levels}, std::move(outputs));
}

ResponseFunction ResponseFunction::sampled(std::array<std::vector<double>, 3> levels,
                                           std::array<std::vector<double>, 3> outputs) {
    for (std::size_t c = 0; c < 3; ++c) {
        const std::string name = channelName(c);
        const auto& channelLevels = levels[c];
        auto& channel = outputs[c];
        if (channelLevels.size() < 2) {
            throw std::invalid_argument("response: " + name + " needs at least 2 samples");
        }
        if (channelLevels.front() != 0.0 || channelLevels.back() != 1.0) {
            throw std::invalid_argument("response: " + name + " levels must run from 0 to 1");
        }
        for (std::size_t k = 1; k < channelLevels.size(); ++k) {
            if (!(channelLevels[k] > channelLevels[k - 1])) {
                throw std::invalid_argument("response: " + name + " level " + std::to_string(k) +
                                            " is not above the one before");
            }
        }
        if (channel.size() != channelLevels.size()) {
            throw std::invalid_argument("response: " + name + " has " +
                                        std::to_string(channel.size()) + " outputs for " +
                                        std::to_string(channelLevels.size()) + " levels");
        }
        for (std::size_t k = 0; k < channel.size(); ++k) {
            if (!std::isfinite(channel[k]) || channel[k] < 0) {
                throw std::invalid_argument("response: " + name + " sample " + std::to_string(k) +
                                            " is not a finite value ≥ 0");
            }
            if (k > 0 && channel[k] < channel[k - 1]) {
                throw std::invalid_argument("response: " + name + " sample " + std::to_string(k) +
                                            " is below the one before");
            }
        }
        if (!(channel.back() > channel.front())) {
            throw std::invalid_argument("response: " + name + " does not rise");
        }
        const double full = channel.back();
        for (double& value : channel) {
            value /= full;
        }
        channel.back() = 1.0;  // exactly, whatever the division rounded to
    }
    ResponseFunction response;
    response.levels_ = std::move(levels);
    response.outputs_ = std::move(outputs);
    return response;
}

double ResponseFunction::output(int channel, double level) const {
    level = std::isnan(level) ? 0.0 : std::clamp(level, 0.0, 1.0);
    const auto c = static_cast<std::size_t>(channel);
    if (isGamma()) {
        return std::pow(level, exponents_[c]);
    }
    const auto& levels = levels_[c];
    const auto& outputs = outputs_[c];
    const auto upper = std::upper_bound(levels.begin(), levels.end(), level);
    if (upper == levels.end()) {
        return outputs.back();
    }
    const auto k = static_cast<std::size_t>(std::distance(levels.begin(), upper));  // ≥ 1
    const double f = (level - levels[k - 1]) / (levels[k] - levels[k - 1]);
    return outputs[k - 1] + f * (outputs[k] - outputs[k - 1]);
}

double ResponseFunction::level(int channel, double fraction) const {
    if (std::isnan(fraction)) {
        return 0.0;
    }
    const auto c = static_cast<std::size_t>(channel);
    if (isGamma()) {
        return std::pow(std::clamp(fraction, 0.0, 1.0), 1.0 / exponents_[c]);
    }
    const auto& outputs = outputs_[c];
    if (fraction <= outputs.front()) {
        return 0.0;
    }
    // First sample at or above the fraction (for fraction ≥ 1: the first at full output, as
    // a curve may saturate before level 1); the one before is below it, so the segment between
    // them rises and the division is safe.
    const auto k = static_cast<std::size_t>(
        std::distance(outputs.begin(),
                      std::lower_bound(outputs.begin(), outputs.end(), std::min(fraction, 1.0))));
    const double f = (std::min(fraction, 1.0) - outputs[k - 1]) / (outputs[k] - outputs[k - 1]);
    const auto& levels = levels_[c];
    return std::clamp(levels[k - 1] + f * (levels[k] - levels[k - 1]), 0.0, 1.0);
}

InverseResponseTable::InverseResponseTable(const ResponseFunction& response, int samples)
    : samples_(samples) {
    if (samples < 2) {
        throw std::invalid_argument("an inverse response table needs at least 2 samples");
    }
    for (int c = 0; c < 3; ++c) {
        std::vector<float>& levels = levels_[static_cast<std::size_t>(c)];
        for (int i = 0; i < samples; ++i) {
            const double u = static_cast<double>(i) / (samples - 1);
            // Held to half precision, as the device's RGBA16F texture (filterable in GLES 3.0,
            // unlike RGBA32F) holds it: CPU and GPU look up the same numbers.
            levels.push_back(
                halfToFloat(floatToHalf(static_cast<float>(response.level(c, u * u)))));
        }
    }
}

double InverseResponseTable::level(int channel, double relative) const {
    const double r = std::isnan(relative) ? 0.0 : std::clamp(relative, 0.0, 1.0);
    const double x = std::sqrt(r) * (samples_ - 1);
    const int i = std::min(static_cast<int>(x), samples_ - 2);
    const double f = x - i;
    const std::vector<float>& levels = levels_[static_cast<std::size_t>(channel)];
    return static_cast<double>(levels[static_cast<std::size_t>(i)]) * (1 - f) +
           static_cast<double>(levels[static_cast<std::size_t>(i) + 1]) * f;
}

ResponseFunction responseFunctionOf(const ResponseCurves& curves) {
    if (curves.kind == ResponseKind::kGamma) {
        return ResponseFunction::gamma({static_cast<double>(curves.gamma[0]),
                                        static_cast<double>(curves.gamma[1]),
                                        static_cast<double>(curves.gamma[2])});
    }
    std::array<std::vector<double>, 3> levels, outputs;
    for (std::size_t ch = 0; ch < 3; ++ch) {
        const std::vector<float>& curve = curves.curve[ch];
        for (std::size_t i = 0; i < curve.size(); ++i) {
            levels[ch].push_back(static_cast<double>(i) / static_cast<double>(curve.size() - 1));
            outputs[ch].push_back(static_cast<double>(curve[i]));
        }
    }
    return ResponseFunction::sampled(std::move(levels), std::move(outputs));
}

}  // namespace vpe::proto
