#include <mrpt/core/exceptions.h>
#include <superloc/core/errors.h>

#include <sstream>

namespace superloc {

std::string oneLineError(const std::exception& e) {
    std::istringstream text(mrpt::exception_to_str(e));
    const char* blanks = " \t\r:";
    for (std::string line; std::getline(text, line);) {
        const size_t frame = line.find("====");
        if (frame != std::string::npos) line.erase(frame);
        if (line.rfind("Message:", 0) == 0) line.erase(0, 8);
        const size_t a = line.find_first_not_of(blanks);
        if (a == std::string::npos) continue;
        return line.substr(a, line.find_last_not_of(blanks) + 1 - a);
    }
    return e.what()[0] ? std::string(e.what()) : std::string("unknown error");
}

}  // namespace superloc
