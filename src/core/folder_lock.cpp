#include "deepsea/core/folder_lock.h"

#include <fcntl.h>
#include <sys/file.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <filesystem>
#include <string>

#include "deepsea/core/error.h"

namespace deepsea {

namespace {

std::string read_owner(int fd) {
    char buf[32] = {};
    const ssize_t n = ::pread(fd, buf, sizeof buf - 1, 0);
    std::string pid = n > 0 ? std::string(buf, std::size_t(n)) : std::string();
    while (!pid.empty() && (pid.back() == '\n' || pid.back() == ' ')) pid.pop_back();
    return pid.find_first_not_of("0123456789") == std::string::npos ? pid : std::string();
}

}  // namespace

FolderLock::FolderLock(const std::string& folder, Mode mode, const std::string& name)
    : m_path((std::filesystem::path(folder) / name).string()), m_mode(mode) {
    // The file may be unlinked by its previous owner between our open and our lock; then the
    // lock we got is on a name no one else will open: check the inode and try again.
    for (int attempt = 0; attempt < 8; ++attempt) {
        const int fd = ::open(m_path.c_str(), O_RDWR | O_CREAT | O_CLOEXEC, 0644);
        if (fd < 0) {
            throw IoError(folder + ": cannot create the lock file " + name + ": " +
                          std::strerror(errno));
        }
        if (::flock(fd, (mode == Mode::Shared ? LOCK_SH : LOCK_EX) | LOCK_NB) != 0) {
            const int err = errno;
            const std::string owner = read_owner(fd);
            ::close(fd);
            if (err == EWOULDBLOCK) {
                throw IoError(folder + ": another deepsea process" +
                              (owner.empty() ? std::string() : " (pid " + owner + ")") +
                              " is writing into this folder; wait for it or choose another");
            }
            throw IoError(folder + ": cannot lock " + name + ": " + std::strerror(err));
        }
        struct stat held {
        }, named{};
        if (::fstat(fd, &held) == 0 && ::stat(m_path.c_str(), &named) == 0 &&
            held.st_ino == named.st_ino && held.st_dev == named.st_dev) {
            // Shared holders would overwrite each other's ids: only an exclusive one writes.
            const std::string pid = std::to_string(::getpid()) + "\n";
            if (mode == Mode::Exclusive && ::ftruncate(fd, 0) == 0 &&
                ::pwrite(fd, pid.data(), pid.size(), 0) < 0) {
                // The pid is only for messages: a lock without it still excludes others.
            }
            m_fd = fd;
            return;
        }
        ::close(fd);
    }
    throw IoError(folder + ": cannot lock " + name + ": it keeps being replaced");
}

FolderLock::~FolderLock() {
    if (m_fd < 0) return;
    // Unlink while still holding the lock: a process that opened the old file gets the lock
    // only after this and then sees that the name no longer refers to it. A shared holder
    // unlinks only as the last one (an exclusive lock granted now), else the others' lock
    // would be on a name a newcomer no longer finds.
    if (m_mode == Mode::Exclusive || ::flock(m_fd, LOCK_EX | LOCK_NB) == 0)
        ::unlink(m_path.c_str());
    ::close(m_fd);
}

}  // namespace deepsea
