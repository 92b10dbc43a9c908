#include "deepsea/core/atomic_file.h"

#include <gtest/gtest.h>
#include <sys/stat.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>
#include <vector>

#include "../temp_folder.h"
#include "deepsea/core/error.h"

namespace deepsea {

namespace fs = std::filesystem;

namespace {

class AtomicFile : public test::TempFolderTest {};

void put(const std::string& path, const std::string& text) { std::ofstream(path) << text; }

std::string get(const std::string& path) {
    std::ifstream f(path);
    return {std::istreambuf_iterator<char>(f), std::istreambuf_iterator<char>()};
}

}  // namespace

TEST_F(AtomicFile, ReplacesTheTargetOnSuccess) {
    put(path("a.txt"), "old");
    std::string tmp_seen;
    write_atomically(path("a.txt"), [&](const std::string& tmp) {
        tmp_seen = tmp;
        EXPECT_EQ(fs::path(tmp).parent_path(), dir_);  // same folder: the rename is atomic
        EXPECT_EQ(fs::path(tmp).extension(), ".txt");  // format-by-extension writers agree
        EXPECT_EQ(get(path("a.txt")), "old");          // readers see the old file meanwhile
        put(tmp, "new");
    });
    EXPECT_EQ(get(path("a.txt")), "new");
    EXPECT_FALSE(fs::exists(tmp_seen));
    EXPECT_EQ(listing(), std::vector<std::string>{"a.txt"});
}

TEST_F(AtomicFile, WriterThatThrowsLeavesNoTemporaryAndTheOldFile) {
    put(path("a.txt"), "old");
    EXPECT_THROW(write_atomically(path("a.txt"),
                                  [&](const std::string& tmp) {
                                      put(tmp, "half");
                                      throw InputError("writer failed");
                                  }),
                 InputError);  // the writer's own exception
    EXPECT_EQ(get(path("a.txt")), "old");
    EXPECT_EQ(listing(), std::vector<std::string>{"a.txt"});
}

TEST_F(AtomicFile, WriterThatWritesNothingIsAnIoErrorAndLeavesNoFile) {
    EXPECT_THROW(write_atomically(path("none.txt"), [](const std::string&) {}), IoError);
    EXPECT_THROW(write_atomically(path("empty.txt"), [](const std::string& tmp) { put(tmp, ""); }),
                 IoError);
    EXPECT_TRUE(listing().empty());
}

TEST_F(AtomicFile, RefusesAMissingFolderBeforeWriting) {
    bool called = false;
    const std::string target = path("no/such/dir/a.txt");
    try {
        write_atomically(target, [&](const std::string&) { called = true; });
        FAIL() << "no exception";
    } catch (const IoError& e) {
        EXPECT_NE(std::string(e.what()).find(target), std::string::npos) << e.what();
    }
    EXPECT_FALSE(called);
    EXPECT_THROW(require_writable_folder(target), IoError);
    put(path("file"), "x");
    EXPECT_THROW(require_writable_folder(path("file/a.txt")), IoError);  // not a folder
    EXPECT_NO_THROW(require_writable_folder(path("a.txt")));
}

TEST_F(AtomicFile, RenameOntoAFolderFailsAndCleansUp) {
    fs::create_directories(path("busy.txt"));
    EXPECT_THROW(write_atomically(path("busy.txt"), [](const std::string& tmp) { put(tmp, "x"); }),
                 IoError);
    EXPECT_EQ(listing(), std::vector<std::string>{"busy.txt"});
}

TEST_F(AtomicFile, AFullDeviceIsAnIoErrorNamingTheFile) {
    // /dev/full answers every write with ENOSPC, as a full disk does.
    if (!fs::exists("/dev/full")) GTEST_SKIP() << "no /dev/full";
    try {
        write_fully("/dev/full", std::string(100000, 'x'), "out.vdb");
        FAIL() << "no IoError";
    } catch (const IoError& e) {
        EXPECT_EQ(std::string(e.what()).rfind("out.vdb: write failed: ", 0), 0u) << e.what();
        EXPECT_NE(std::string(e.what()).find("No space left"), std::string::npos) << e.what();
    }
}

TEST_F(AtomicFile, WriteFullyWritesEveryByte) {
    std::string bytes(3 << 20, '\0');
    for (std::size_t i = 0; i < bytes.size(); ++i) bytes[i] = char(i * 2654435761u >> 24);
    write_fully(path("b.bin"), bytes, "b.bin");
    EXPECT_EQ(get(path("b.bin")), bytes);
}

TEST_F(AtomicFile, OutputsMayNotBeTheirInputs) {
    put(path("in.yaml"), "camera: {}\n");
    fs::create_symlink(path("in.yaml"), path("link.yaml"));
    const std::vector<std::pair<std::string, std::string>> in{{path("in.yaml"), "the input"}};
    EXPECT_THROW(require_distinct(path("in.yaml"), in), IoError);
    EXPECT_THROW(require_distinct(path("link.yaml"), in), IoError);  // through a link
    EXPECT_THROW(require_distinct(path("./in.yaml"), in), IoError);
    EXPECT_NO_THROW(require_distinct(path("out.yaml"), in));
    EXPECT_NO_THROW(require_distinct(path("in.yaml"), {{"", "nothing"}}));
    // Two outputs still to be written, at the same place under two spellings.
    EXPECT_THROW(require_distinct(path("x.exr"), {{path("sub/../x.exr"), "the -o output"}}),
                 IoError);
    try {
        require_distinct(path("in.yaml"), in);
    } catch (const IoError& e) {
        EXPECT_EQ(std::string(e.what()), path("in.yaml") + ": is the same file as the input " +
                                             path("in.yaml") + " (choose another output)");
    }
}

}  // namespace deepsea

namespace deepsea {

TEST_F(AtomicFile, TemporaryNamesAreRecognisedWithTheirTargetAndWriter) {
    for (const std::string name : {"frame_0001.png", "a.b.exr", "noext", "deepsea-sequence.json"}) {
        std::string tmp_name;
        write_atomically(path(name), [&](const std::string& tmp) {
            tmp_name = fs::path(tmp).filename();
            put(tmp, "x");
        });
        const auto parsed = parse_temporary_name(tmp_name);
        ASSERT_TRUE(parsed) << tmp_name;
        EXPECT_EQ(parsed->target, name);
        EXPECT_EQ(parsed->pid, long(::getpid()));
    }
    for (const std::string name : {"frame_0001.png", ".hidden.png", ".a.tmp-x-1.png",
                                   ".a.tmp-12.png", ".tmp-1-2.png", ".a.tmp-1-2x.png"}) {
        EXPECT_FALSE(parse_temporary_name(name)) << name;
    }
}

}  // namespace deepsea

namespace deepsea {

TEST_F(AtomicFile, ALinkToAFileIsWrittenThroughAndStaysALink) {
    put(path("shared.yaml"), "old");
    fs::create_symlink(path("shared.yaml"), path("setup.yaml"));
    write_text_atomically(path("setup.yaml"), "new");
    EXPECT_TRUE(fs::is_symlink(path("setup.yaml")));
    EXPECT_EQ(get(path("shared.yaml")), "new");
    // A link to a link to a file: the file at the end.
    fs::create_symlink(path("setup.yaml"), path("again.yaml"));
    write_text_atomically(path("again.yaml"), "newer");
    EXPECT_TRUE(fs::is_symlink(path("again.yaml")) && fs::is_symlink(path("setup.yaml")));
    EXPECT_EQ(get(path("shared.yaml")), "newer");
}

TEST_F(AtomicFile, LinksToAnythingButAFileAndNonFilesAreRefusedUntouched) {
    if (!fs::exists("/dev/null")) GTEST_SKIP() << "no /dev/null";
    fs::create_symlink("/dev/null", path("null.yaml"));
    fs::create_symlink(path("nowhere"), path("dangling.yaml"));
    fs::create_directory(path("dir"));
    fs::create_symlink(path("dir"), path("dirlink.yaml"));
    ASSERT_EQ(::mkfifo(path("pipe.yaml").c_str(), 0644), 0);
    for (const std::string name : {"null.yaml", "dangling.yaml", "dirlink.yaml", "pipe.yaml"}) {
        bool called = false;
        try {
            write_atomically(path(name), [&](const std::string& tmp) {
                called = true;
                put(tmp, "x");
            });
            ADD_FAILURE() << name << ": no exception";
        } catch (const IoError& e) {
            EXPECT_NE(std::string(e.what()).find(path(name)), std::string::npos) << e.what();
        }
        EXPECT_FALSE(called) << name;
    }
    EXPECT_TRUE(fs::is_symlink(path("null.yaml")));
    EXPECT_TRUE(fs::is_character_file("/dev/null"));
    EXPECT_TRUE(fs::is_symlink(path("dangling.yaml")));
    EXPECT_TRUE(fs::is_fifo(path("pipe.yaml")));
    EXPECT_FALSE(fs::exists(path("nowhere")));
    EXPECT_THROW(write_text_atomically(std::string("a\0b", 3), "x"), IoError);
}

TEST_F(AtomicFile, ALegalLongNameGetsATemporaryThatIsRecognised) {
    for (const std::size_t stem : {200u, 230u, 246u, 251u}) {
        const std::string name = std::string(stem, 'n') + ".png";
        ASSERT_LE(name.size(), 255u);
        std::string tmp_name;
        write_atomically(path(name), [&](const std::string& tmp) {
            tmp_name = fs::path(tmp).filename();
            put(tmp, "x");
        });
        EXPECT_LE(tmp_name.size(), 255u);
        EXPECT_EQ(get(path(name)), "x");
        const auto parsed = parse_temporary_name(tmp_name);
        ASSERT_TRUE(parsed) << tmp_name;
        EXPECT_EQ(parsed->target, temporary_key(name));
        EXPECT_EQ(fs::path(tmp_name).extension(), ".png");
    }
    // Two long names that differ only at their end get different keys.
    EXPECT_NE(temporary_key(std::string(250, 'a') + "1.png"),
              temporary_key(std::string(250, 'a') + "2.png"));
    EXPECT_EQ(temporary_key("frame_0001.png"), "frame_0001.png");
}

TEST_F(AtomicFile, ResolvedPathsApplyDotsAfterMissingFolders) {
    fs::create_directory(path("in"));
    fs::create_symlink(path("in"), path("link"));
    const fs::path in = resolved_path(path("in"));
    // A link after missing folders too: once they are made, the kernel follows it.
    for (const std::string p : {"in/nosuch/..", "in/a/b/../..", "in/./x/../", "in/", "link",
                                "link/nosuch/..", "nosuch/../link", "a.png/../link/x/.."})
        EXPECT_EQ(resolved_path(path(p)), in) << p;
    EXPECT_NE(resolved_path(path("in/nosuch")), in);
    EXPECT_TRUE(same_file(path("in/nosuch/../f.png"), path("link/f.png")));
    EXPECT_FALSE(same_file(path("in/f.png"), path("in/g.png")));
}

}  // namespace deepsea
