// floor() to an integer without the libm call that std::floor compiles to on x86-64 without
// SSE4.1 (the project assumes no more than the base instruction set). Exact for every finite
// value whose floor fits in int64_t; callers guarantee that (range filters, bounds checks).
#pragma once

#include <cstdint>

namespace superloc {

inline int64_t floorToInt(float s) {
    const int64_t i = static_cast<int64_t>(s);  // truncates toward zero
    return i - (static_cast<float>(i) > s);     // one less for negative non-integers
}

}  // namespace superloc
