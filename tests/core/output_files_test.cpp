// OutputFiles: outputs are written all or nothing; a failure leaves every pre-existing file
// byte-identical and no temporary file behind; outputs equal to inputs or to each other are
// refused before anything is written.
#include "ngi/output_files.h"

#include "ngi/asset.h"
#include "ngi/error.h"

#include <gtest/gtest.h>

#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

#include <csignal>

#include <algorithm>
#include <filesystem>
#include <functional>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

namespace {

namespace fs = std::filesystem;

std::span<const uint8_t> bytesOf(const std::string& text)
{
    return {reinterpret_cast<const uint8_t*>(text.data()), text.size()};
}

class OutputFilesTest : public ::testing::Test {
protected:
    void SetUp() override
    {
        dir_ = fs::temp_directory_path() /
            ("ngi_output_files_" + std::to_string(::getpid()) + "_" +
             ::testing::UnitTest::GetInstance()->current_test_info()->name());
        fs::remove_all(dir_);
        fs::create_directories(dir_);
    }
    void TearDown() override { fs::remove_all(dir_); }
    fs::path file(const std::string& name) const { return dir_ / name; }
    void put(const std::string& name, const std::string& text) const
    {
        std::ofstream(file(name), std::ios::binary) << text;
    }
    std::string get(const std::string& name) const
    {
        std::ifstream in(file(name), std::ios::binary);
        std::stringstream s;
        s << in.rdbuf();
        return s.str();
    }
    // The names in dir_, sorted: no temporary file may stay behind.
    std::vector<std::string> names() const
    {
        std::vector<std::string> result;
        for (const auto& e : fs::directory_iterator(dir_)) result.push_back(e.path().filename().string());
        std::sort(result.begin(), result.end());
        return result;
    }
    std::string message(const std::function<void()>& f) const
    {
        try {
            f();
        } catch (const ngi::Error& e) {
            return e.what();
        }
        return "";
    }
    fs::path dir_;
};

TEST_F(OutputFilesTest, CommitRenamesEveryStagedFileAndLeavesNoTemporary)
{
    put("a.txt", "old a");
    ngi::OutputFiles files({file("a.txt"), file("b.obj")});
    files.write(file("a.txt"), bytesOf("new a"));
    const fs::path staged = files.stage(file("b.obj"));
    EXPECT_EQ(staged.parent_path(), dir_);
    EXPECT_EQ(staged.extension(), ".obj");  // writers choosing the format by extension still can
    EXPECT_EQ(files.stage(file("b.obj")), staged);
    ngi::writeFileAtomic(staged, bytesOf("new b"));  // a writer may replace the staged file
    EXPECT_EQ(get("a.txt"), "old a");                // nothing replaced before commit
    EXPECT_FALSE(fs::exists(file("b.obj")));
    files.commit();
    EXPECT_EQ(get("a.txt"), "new a");
    EXPECT_EQ(get("b.obj"), "new b");
    EXPECT_EQ(names(), (std::vector<std::string>{"a.txt", "b.obj"}));
}

TEST_F(OutputFilesTest, WriteWithNamesTheDestinationInErrors)
{
    ngi::OutputFiles files({file("a.ngi")});
    const std::string m = message([&] {
        files.writeWith(file("a.ngi"),
                        [](const fs::path& temporary) { throw ngi::Error(temporary.string() + ": write failed"); });
    });
    EXPECT_EQ(m, file("a.ngi").string() + ": write failed");
    files.writeWith(file("a.ngi"), [](const fs::path& temporary) { ngi::writeFileAtomic(temporary, bytesOf("a")); });
    files.commit();
    EXPECT_EQ(get("a.ngi"), "a");
    EXPECT_EQ(names(), (std::vector<std::string>{"a.ngi"}));
}

TEST_F(OutputFilesTest, AnUncommittedTransactionLeavesEveryFileAsItWas)
{
    put("a.txt", "old a");
    put("b.txt", "old b");
    {
        ngi::OutputFiles files({file("a.txt"), file("b.txt"), file("c.txt")});
        files.write(file("a.txt"), bytesOf("new a"));
        files.write(file("b.txt"), bytesOf("new b"));
        // The run fails here (an exception): the destructor removes the temporaries.
    }
    EXPECT_EQ(get("a.txt"), "old a");
    EXPECT_EQ(get("b.txt"), "old b");
    EXPECT_EQ(names(), (std::vector<std::string>{"a.txt", "b.txt"}));
}

TEST_F(OutputFilesTest, CommitRefusesWhenADeclaredOutputWasNotWritten)
{
    put("a.txt", "old a");
    ngi::OutputFiles files({file("a.txt"), file("b.txt")});
    files.write(file("a.txt"), bytesOf("new a"));
    EXPECT_NE(message([&] { files.commit(); }).find("b.txt: this output was never written"), std::string::npos);
    EXPECT_EQ(get("a.txt"), "old a");  // nothing renamed: all or nothing
}

TEST_F(OutputFilesTest, BadOutputPathsFailWhenDeclared)
{
    fs::create_directories(file("dir"));
    EXPECT_NE(message([&] { ngi::OutputFiles files({file("dir")}); }).find("dir: is a directory"), std::string::npos);
    EXPECT_NE(message([&] { ngi::OutputFiles files({file("none/x.ngi")}); }).find("x.ngi: cannot create file"),
              std::string::npos);
    EXPECT_NE(message([&] {
                  ngi::OutputFiles files({file("x.ngi"), dir_ / "dir" / ".." / "x.ngi"});
              }).find("every output needs its own path"),
              std::string::npos);
    ngi::OutputFiles files({file("x.ngi")});
    EXPECT_NE(message([&] { files.stage(file("y.ngi")); }).find("not a declared output"), std::string::npos);
    EXPECT_EQ(names(), (std::vector<std::string>{"dir"}));
}

TEST_F(OutputFilesTest, OutputsEqualToAnInputAreRefused)
{
    put("in.off", "mesh");
    fs::create_symlink(file("in.off"), file("link.off"));
    fs::create_hard_link(file("in.off"), file("hard.off"));
    for (const fs::path& out : {file("in.off"), dir_ / "." / "in.off", file("link.off"), file("hard.off")}) {
        SCOPED_TRACE(out);
        const std::string m = message([&] { ngi::OutputFiles files({out}, {file("in.off")}); });
        EXPECT_NE(m.find("this output is the input"), std::string::npos) << m;
        EXPECT_NE(m.find(out.string()), std::string::npos) << m;
    }
    // An input that does not exist yet (e.g. a directory given twice) compares by path.
    EXPECT_THROW(ngi::refuseOutputEqualToInput({file("new.ngi")}, {dir_ / "sub" / ".." / "new.ngi"}), ngi::Error);
    EXPECT_NO_THROW(ngi::refuseOutputEqualToInput({file("out.ngi"), {}}, {file("in.off"), {}}));
    EXPECT_EQ(get("in.off"), "mesh");
}

TEST_F(OutputFilesTest, AMovedTransactionOwnsTheTemporaries)
{
    ngi::OutputFiles moved;
    {
        ngi::OutputFiles files({file("a.txt")});
        files.write(file("a.txt"), bytesOf("a"));
        moved = std::move(files);
    }
    EXPECT_EQ(names().size(), 1u);  // the temporary survives the moved-from object
    moved.commit();
    EXPECT_EQ(get("a.txt"), "a");
    EXPECT_EQ(names(), (std::vector<std::string>{"a.txt"}));
}

TEST_F(OutputFilesTest, WriteFileAtomicReplacesOrLeavesTheFile)
{
    put("a.txt", "old");
    ngi::writeFileAtomic(file("a.txt"), bytesOf("new"));
    EXPECT_EQ(get("a.txt"), "new");
    fs::create_directories(file("dir"));
    EXPECT_THROW(ngi::writeFileAtomic(file("dir"), bytesOf("x")), ngi::Error);
    EXPECT_EQ(names(), (std::vector<std::string>{"a.txt", "dir"}));
}

TEST_F(OutputFilesTest, DevicesAndFifosAreRefusedAndLeftAsTheyAre)
{
    ASSERT_EQ(::mkfifo(file("pipe.ngi").c_str(), 0600), 0);
    std::string m = message([&] { ngi::OutputFiles files({file("pipe.ngi")}); });
    EXPECT_EQ(m, file("pipe.ngi").string() + ": is a FIFO, not a regular file; refusing to replace it");
    EXPECT_THROW(ngi::writeFileAtomic(file("pipe.ngi"), bytesOf("x")), ngi::Error);
    EXPECT_TRUE(fs::is_fifo(fs::symlink_status(file("pipe.ngi"))));

    // /dev/null is refused without being opened, so this test cannot damage it.
    ASSERT_TRUE(fs::is_character_file(fs::symlink_status("/dev/null")));
    m = message([&] { ngi::writeFileAtomic("/dev/null", bytesOf("x")); });
    EXPECT_EQ(m, "/dev/null: is a character device, not a regular file; refusing to replace it");
    EXPECT_TRUE(fs::is_character_file(fs::symlink_status("/dev/null")));

    // A destination that becomes a FIFO while the run writes is not renamed over either.
    {
        ngi::OutputFiles files({file("late.ngi")});
        files.write(file("late.ngi"), bytesOf("late"));
        ASSERT_EQ(::mkfifo(file("late.ngi").c_str(), 0600), 0);
        m = message([&] { files.commit(); });
        EXPECT_EQ(m, file("late.ngi").string() + ": is a FIFO, not a regular file; refusing to replace it");
    }
    EXPECT_TRUE(fs::is_fifo(fs::symlink_status(file("late.ngi"))));
    EXPECT_EQ(names(), (std::vector<std::string>{"late.ngi", "pipe.ngi"}));
    EXPECT_TRUE(fs::is_character_file(fs::symlink_status("/dev/null")));
}

TEST_F(OutputFilesTest, ASymbolicLinkIsWrittenThroughAndStaysALink)
{
    fs::create_directories(file("sub"));
    std::ofstream(file("sub/target.ngi"), std::ios::binary) << "old";
    fs::create_symlink(fs::path("sub") / "target.ngi", file("link.ngi"));
    ngi::writeFileAtomic(file("link.ngi"), bytesOf("new"));
    EXPECT_TRUE(fs::is_symlink(fs::symlink_status(file("link.ngi"))));
    EXPECT_EQ(get("sub/target.ngi"), "new");
    EXPECT_EQ(names(), (std::vector<std::string>{"link.ngi", "sub"}));
    EXPECT_EQ(std::distance(fs::directory_iterator(file("sub")), fs::directory_iterator()), 1);  // no temporary

    // A link whose target is missing, a FIFO or a device is refused, and stays a link.
    fs::create_symlink("missing.ngi", file("dangling.ngi"));
    EXPECT_EQ(message([&] { ngi::writeFileAtomic(file("dangling.ngi"), bytesOf("x")); }),
              file("dangling.ngi").string() +
                  ": is a symbolic link whose target does not exist; refusing to replace the link (name the "
                  "target, or remove the link)");
    ASSERT_EQ(::mkfifo(file("pipe").c_str(), 0600), 0);
    fs::create_symlink("pipe", file("to_pipe.ngi"));
    EXPECT_NE(message([&] { ngi::writeFileAtomic(file("to_pipe.ngi"), bytesOf("x")); })
                  .find("to_pipe.ngi: is a symbolic link to '" + file("pipe").string() +
                        "', which is a FIFO, not a regular file; refusing to replace it"),
              std::string::npos);
    fs::create_symlink("/dev/null", file("to_null.ngi"));
    EXPECT_NE(
        message([&] { ngi::writeFileAtomic(file("to_null.ngi"), bytesOf("x")); }).find("which is a character device"),
        std::string::npos);
    for (const char* link : {"link.ngi", "dangling.ngi", "to_pipe.ngi", "to_null.ngi"})
        EXPECT_TRUE(fs::is_symlink(fs::symlink_status(file(link)))) << link;
    EXPECT_TRUE(fs::is_character_file(fs::symlink_status("/dev/null")));

    // A destination that becomes a symbolic link while the run writes is not renamed over.
    {
        ngi::OutputFiles files({file("late.ngi")});
        files.write(file("late.ngi"), bytesOf("late"));
        fs::create_symlink(fs::path("sub") / "target.ngi", file("late.ngi"));
        EXPECT_NE(message([&] { files.commit(); }).find("late.ngi: changed while this run wrote it"),
                  std::string::npos);
    }
    EXPECT_TRUE(fs::is_symlink(fs::symlink_status(file("late.ngi"))));
    EXPECT_EQ(get("sub/target.ngi"), "new");
    EXPECT_EQ(names(),
              (std::vector<std::string>{"dangling.ngi", "late.ngi", "link.ngi", "pipe", "sub", "to_null.ngi",
                                        "to_pipe.ngi"}));
}

// An empty output path (`-o ''`) is named as such, not as an internal error.
TEST_F(OutputFilesTest, AnEmptyOutputPathIsNamedAsEmpty)
{
    ngi::OutputFiles files({fs::path()});  // an optional output not given: skipped
    EXPECT_EQ(message([&] { files.stage(fs::path()); }), "the output path is empty");
    EXPECT_EQ(message([&] { files.add(fs::path()); }), "the output path is empty");
    EXPECT_EQ(message([] { ngi::writeFileAtomic(fs::path(), {}); }), "the output path is empty");
}

// A run ended by SIGINT or SIGTERM while its outputs are staged leaves no temporary file and
// no output, and still ends by that signal (its exit status says so).
TEST_F(OutputFilesTest, AnInterruptedRunLeavesNoTemporaryFile)
{
    put("old.ngi", "old");
    for (const int signal : {SIGINT, SIGTERM}) {
        SCOPED_TRACE(signal);
        const pid_t child = ::fork();
        ASSERT_GE(child, 0);
        if (child == 0) {
            ngi::OutputFiles files({file("old.ngi"), file("new.obj")});
            files.write(file("old.ngi"), bytesOf("new"));
            files.stage(file("new.obj"));
            ::raise(signal);
            ::_exit(0);  // not reached
        }
        int status = 0;
        ASSERT_EQ(::waitpid(child, &status, 0), child);
        EXPECT_TRUE(WIFSIGNALED(status) && WTERMSIG(status) == signal) << status;
        EXPECT_EQ(names(), (std::vector<std::string>{"old.ngi"}));
        EXPECT_EQ(get("old.ngi"), "old");
    }
}

}  // namespace
