#include <mrpt/system/COutputLogger.h>
#include <superloc/io/json_file.h>

#include <cmath>
#include <fstream>
#include <nlohmann/json.hpp>
#include <sstream>
#include <stdexcept>

namespace superloc::io {

namespace {

void replaceNonFinite(Json& j, const Json::json_pointer& at,
                      std::vector<std::string>& replaced) {
    if (j.is_number_float()) {
        if (!std::isfinite(j.get<double>())) {
            j = nullptr;
            replaced.push_back(at.to_string());
        }
    } else if (j.is_object()) {
        for (auto& [key, value] : j.items()) replaceNonFinite(value, at / key, replaced);
    } else if (j.is_array()) {
        for (size_t i = 0; i < j.size(); ++i) replaceNonFinite(j[i], at / i, replaced);
    }
}

mrpt::system::COutputLogger& ioLogger() {
    static mrpt::system::COutputLogger logger("superloc::io::json");
    return logger;
}

}  // namespace

std::vector<std::string> replaceNonFinite(Json& j) {
    std::vector<std::string> replaced;
    replaceNonFinite(j, Json::json_pointer(), replaced);
    return replaced;
}

std::string toJsonText(const Json& j, const std::string& what,
                       mrpt::system::COutputLogger* log) {
    Json clean = j;
    const auto replaced = replaceNonFinite(clean);
    auto& logger = log ? *log : ioLogger();
    for (const auto& p : replaced)
        logger.logFmt(mrpt::system::LVL_WARN, "%s: non-finite number at %s written as null\n",
                      what.c_str(), p.c_str());
    // error_handler::replace: invalid UTF-8 in a string (a file name, a message) becomes U+FFFD
    // instead of an exception.
    return clean.dump(2, ' ', false, Json::error_handler_t::replace) + "\n";
}

void saveJson(const std::string& path, const Json& j, mrpt::system::COutputLogger* log) {
    const std::string text = toJsonText(j, path, log);
    std::ofstream f(path, std::ios::binary);
    if (!f) throw std::runtime_error(path + ": cannot open for writing");
    f << text;
    f.close();
    if (!f) throw std::runtime_error(path + ": write failed");
}

Json loadJson(const std::string& path) {
    std::ifstream f(path, std::ios::binary);
    if (!f) throw std::runtime_error(path + ": cannot open");
    try {
        return Json::parse(f);
    } catch (const nlohmann::json::exception& e) {
        std::string msg = e.what();
        for (char& c : msg)
            if (c == '\n' || c == '\r') c = ' ';
        throw std::runtime_error(path + ": not valid JSON (" + msg + ")");
    }
}

}  // namespace superloc::io
