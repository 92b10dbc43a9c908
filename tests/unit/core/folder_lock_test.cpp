#include "deepsea/core/folder_lock.h"

#include <gtest/gtest.h>

#include <filesystem>
#include <memory>

#include "../temp_folder.h"
#include "deepsea/core/error.h"

namespace deepsea {

namespace fs = std::filesystem;

namespace {

class FolderLockTest : public test::TempFolderTest {};

}  // namespace

TEST_F(FolderLockTest, SecondWriterIsRefusedUntilTheFirstIsDone) {
    {
        const FolderLock first(dir_.string());
        EXPECT_TRUE(fs::exists(dir_ / FolderLock::file_name()));
        // flock locks belong to the open file, so a second lock in this process conflicts
        // just as another process's would.
        try {
            const FolderLock second(dir_.string());
            FAIL() << "a second lock on the same folder was granted";
        } catch (const IoError& e) {
            EXPECT_NE(std::string(e.what()).find("another deepsea process"), std::string::npos)
                << e.what();
        }
    }
    EXPECT_FALSE(fs::exists(dir_ / FolderLock::file_name()));  // released: file removed
    const FolderLock again(dir_.string());
}

TEST_F(FolderLockTest, SharedHoldersCoexistAndExcludeAnExclusiveOne) {
    using Mode = FolderLock::Mode;
    {
        auto a = std::make_unique<FolderLock>(dir_.string(), Mode::Shared);
        const FolderLock b(dir_.string(), Mode::Shared);  // the shards of one render
        EXPECT_THROW(FolderLock(dir_.string()), IoError);
        a.reset();  // not the last holder: the file stays, and still excludes
        EXPECT_TRUE(fs::exists(dir_ / FolderLock::file_name()));
        EXPECT_THROW(FolderLock(dir_.string()), IoError);
    }
    EXPECT_FALSE(fs::exists(dir_ / FolderLock::file_name()));  // the last one removed it
    {
        const FolderLock only(dir_.string());
        EXPECT_THROW(FolderLock(dir_.string(), Mode::Shared), IoError);
    }
    // Another name is another lock.
    const FolderLock main(dir_.string(), Mode::Shared);
    const FolderLock shard(dir_.string(), Mode::Exclusive, ".deepsea.shard-0000-of-0002.lock");
    EXPECT_THROW(FolderLock(dir_.string(), Mode::Exclusive, ".deepsea.shard-0000-of-0002.lock"),
                 IoError);
}

TEST_F(FolderLockTest, AMissingFolderIsAnIoError) {
    EXPECT_THROW(FolderLock((dir_ / "missing").string()), IoError);
}

}  // namespace deepsea
