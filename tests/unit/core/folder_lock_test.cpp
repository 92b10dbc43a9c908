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

TEST_F(FolderLockTest, AMissingFolderIsAnIoError) {
    EXPECT_THROW(FolderLock((dir_ / "missing").string()), IoError);
}

}  // namespace deepsea
