#include "deepsea/batch/exposure_journal.h"

#include <fcntl.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <filesystem>
#include <nlohmann/json.hpp>

#include "deepsea/core/error.h"
#include "deepsea/core/input_file.h"

namespace deepsea {

using nlohmann::json;

namespace {

FrameExposure exposure_of(const json& j, const std::string& where, const char* key) {
    if (!j.contains(key) || !j[key].is_array() || j[key].size() != 2 || !j[key][0].is_number() ||
        !j[key][1].is_number())
        throw InputError(where + ": " + key +
                         ": expected [exposure_time_ms, system_gain] as two numbers");
    FrameExposure e{j[key][0].get<double>(), j[key][1].get<double>()};
    if (!(e.exposure_time_ms > 0.0) || !(e.system_gain > 0.0))
        throw InputError(where + ": " + key + ": exposure time and gain must be > 0");
    return e;
}

}  // namespace

std::map<std::string, ExposureRecord> read_exposure_journal(const std::string& path) {
    std::map<std::string, ExposureRecord> records;
    std::error_code ec;
    if (!std::filesystem::exists(path, ec)) return records;
    const std::string text = read_text_file(path, "an exposure journal");
    std::size_t begin = 0;
    for (int line = 1; begin < text.size(); ++line) {
        const std::size_t end = text.find('\n', begin);
        if (end == std::string::npos) break;  // cut by a kill while appending: not a record
        const std::string where = path + ":" + std::to_string(line);
        json j;
        try {
            j = json::parse(text.begin() + long(begin), text.begin() + long(end));
        } catch (const json::exception& e) {
            throw InputError(where + ": not an exposure record: " + one_line(e.what()));
        }
        if (!j.is_object() || !j.contains("rgb") || !j["rgb"].is_string())
            throw InputError(where + ": rgb: expected the frame's colour file");
        ExposureRecord r;
        r.rgb = j["rgb"].get<std::string>();
        r.used = exposure_of(j, where, "used");
        r.next = exposure_of(j, where, "next");
        records[r.rgb] = r;
        begin = end + 1;
    }
    return records;
}

void append_exposure_journal(const std::string& path, const ExposureRecord& r) {
    const json j = {{"rgb", r.rgb},
                    {"used", {r.used.exposure_time_ms, r.used.system_gain}},
                    {"next", {r.next.exposure_time_ms, r.next.system_gain}}};
    const std::string line = j.dump() + "\n";
    const int fd = ::open(path.c_str(), O_WRONLY | O_CREAT | O_APPEND | O_CLOEXEC, 0644);
    if (fd < 0) throw IoError(path + ": cannot open for appending: " + std::strerror(errno));
    const ssize_t n = ::write(fd, line.data(), line.size());
    const int write_errno = errno;
    ::close(fd);
    if (n != ssize_t(line.size()))
        throw IoError(path + ": cannot append: " +
                      (n < 0 ? std::strerror(write_errno) : std::string("short write")));
}

}  // namespace deepsea
