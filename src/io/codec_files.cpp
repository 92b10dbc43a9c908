#include "codec_files.h"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>

#include "file_checks.h"

namespace deepsea::io_detail {

BufferPool<DecodeScratch> decode_scratch;

void read_whole_file(const std::string& path, std::vector<std::uint8_t>& bytes) {
    require_readable(path);
    const int fd = ::open(path.c_str(), O_RDONLY | O_CLOEXEC);
    if (fd < 0) io_fail(path, std::strerror(errno));
    struct stat st {};
    if (::fstat(fd, &st) != 0) {
        const int e = errno;
        ::close(fd);
        io_fail(path, std::strerror(e));
    }
    if (st.st_size == 0) {
        ::close(fd);
        io_fail(path, "empty file");
    }
    bytes.resize(std::size_t(st.st_size));
    std::size_t got = 0;
    while (got < bytes.size()) {
        const ssize_t n = ::read(fd, bytes.data() + got, bytes.size() - got);
        if (n < 0 && errno == EINTR) continue;
        if (n <= 0) {
            const int e = errno;
            ::close(fd);
            io_fail(path, n == 0 ? std::string("file shrank while reading") : std::strerror(e));
        }
        got += std::size_t(n);
    }
    ::close(fd);
}

void write_bytes(const std::string& file, const std::uint8_t* bytes, std::size_t size,
                 const std::string& name) {
    const int fd = ::open(file.c_str(), O_WRONLY | O_CREAT | O_TRUNC | O_CLOEXEC, 0666);
    if (fd < 0) io_fail(name, std::strerror(errno));
    std::size_t done = 0;
    while (done < size) {
        const ssize_t n = ::write(fd, bytes + done, size - done);
        if (n < 0 && errno == EINTR) continue;
        if (n <= 0) {
            const int e = n < 0 ? errno : ENOSPC;
            ::close(fd);
            io_fail(name, std::string("write failed: ") + std::strerror(e));
        }
        done += std::size_t(n);
    }
    if (::close(fd) != 0) io_fail(name, std::string("write failed: ") + std::strerror(errno));
}

}  // namespace deepsea::io_detail
