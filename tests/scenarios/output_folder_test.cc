// The output folder's promises: nothing of anyone else's is replaced or deleted, nothing
// half-written is left, writes are checked through close, campaign folders are locked.
#include "scenarios/run/output_folder.h"

#include <unistd.h>

#include <csignal>
#include <filesystem>
#include <fstream>
#include <string>

#include <gmock/gmock.h>
#include <gtest/gtest.h>
#include <sys/resource.h>
#include <sys/stat.h>

#include "common/input_error.h"
#include "tests/cli_test_util.h"

namespace trav::scenarios {
namespace {

namespace fs = std::filesystem;
using ::testing::HasSubstr;

class OutputFolderTest : public ::testing::Test {
 protected:
  void SetUp() override { root_ = test_util::FreshTestFolder("output_folder_test"); }
  void TearDown() override {
    fs::permissions(root_, fs::perms::owner_all, fs::perm_options::add);
    fs::remove_all(root_);
  }
  void Write(const fs::path& path, const std::string& text) {
    fs::create_directories(path.parent_path());
    std::ofstream(path) << text;
  }
  // Makes a committed result of `kind` at `path` holding `file` = `text`.
  void MakeResult(const fs::path& path, const std::string& kind, bool overwrite,
                  const std::string& text) {
    OutputFolder folder(path.string(), kind, overwrite);
    WriteTextFile(folder.File("result.txt"), text);
    folder.Commit();
  }
  fs::path root_;
};

TEST_F(OutputFolderTest, ANewFolderAppearsOnlyWhenCommitted) {
  const fs::path out = root_ / "a" / "b" / "run";
  {
    OutputFolder folder(out.string(), "run", false);
    WriteTextFile(folder.File("result.txt"), "1");
    EXPECT_FALSE(fs::exists(out));
  }
  // never committed: neither the folder nor the parents it made are left
  EXPECT_FALSE(fs::exists(root_ / "a"));
  MakeResult(out, "run", false, "2");
  EXPECT_EQ(test_util::ReadFile(out / "result.txt"), "2");
  EXPECT_EQ(FolderKindOf(out.string()), "run");
}

TEST_F(OutputFolderTest, AFolderOfTheUsersIsNeverReplaced) {
  const fs::path home = root_ / "home";
  Write(home / "thesis.tex", "years of work");
  for (const bool overwrite : {false, true}) {
    EXPECT_THROW(OutputFolder(home.string(), "run", overwrite), common::InputError);
  }
  EXPECT_EQ(test_util::ReadFile(home / "thesis.tex"), "years of work");
  // nor a file
  Write(root_ / "notes.txt", "keep");
  EXPECT_THROW(OutputFolder((root_ / "notes.txt").string(), "run", true), common::InputError);
  EXPECT_EQ(test_util::ReadFile(root_ / "notes.txt"), "keep");
}

TEST_F(OutputFolderTest, AnEarlierResultIsReplacedOnlyWithOverwriteAndOfTheSameKind) {
  const fs::path out = root_ / "run";
  MakeResult(out, "run", false, "first");
  try {
    OutputFolder folder(out.string(), "run", false);
    FAIL() << "an earlier result replaced without --overwrite";
  } catch (const common::InputError& e) {
    EXPECT_THAT(e.what(), HasSubstr("--overwrite"));
  }
  EXPECT_THROW(OutputFolder(out.string(), "terrain", true), common::InputError);
  MakeResult(out, "run", true, "second");
  EXPECT_EQ(test_util::ReadFile(out / "result.txt"), "second");
  // nothing left beside it
  int entries = 0;
  for ([[maybe_unused]] const auto& entry : fs::directory_iterator(root_)) ++entries;
  EXPECT_EQ(entries, 1);
}

TEST_F(OutputFolderTest, AnEmptyFolderIsUsed) {
  const fs::path out = root_ / "empty";
  fs::create_directories(out);
  MakeResult(out, "run", false, "x");
  EXPECT_EQ(test_util::ReadFile(out / "result.txt"), "x");
}

TEST_F(OutputFolderTest, AReadOnlyResultIsNotReplaced) {
  const fs::path out = root_ / "run";
  MakeResult(out, "run", false, "kept");
  fs::permissions(out, fs::perms::owner_write | fs::perms::group_write | fs::perms::others_write,
                  fs::perm_options::remove);
  EXPECT_THROW(OutputFolder(out.string(), "run", true), common::InputError);
  fs::permissions(out, fs::perms::owner_write, fs::perm_options::add);
  EXPECT_EQ(test_util::ReadFile(out / "result.txt"), "kept");
}

TEST_F(OutputFolderTest, AFolderThatAppearsDuringTheRunIsNotReplacedAtCommit) {
  const fs::path out = root_ / "run";
  OutputFolder folder(out.string(), "run", false);
  Write(out / "theirs.txt", "arrived meanwhile");
  EXPECT_THROW(folder.Commit(), common::InputError);
  EXPECT_EQ(test_util::ReadFile(out / "theirs.txt"), "arrived meanwhile");
}

TEST_F(OutputFolderTest, StalePartialFoldersOfDeadProcessesAreRemoved) {
  const fs::path out = root_ / "run";
  // a killed trav's leftover (marked), and a folder of someone else's with a similar name
  const pid_t dead = fork();
  if (dead == 0) _exit(0);
  int status = 0;
  waitpid(dead, &status, 0);
  const fs::path stale = root_ / ("run.partial-" + std::to_string(dead));
  Write(stale / kFolderMarker, R"({"kind": "run"})");
  const fs::path foreign = root_ / "run.partial-1";
  Write(foreign / "data.txt", "not trav's");
  MakeResult(out, "run", false, "x");
  EXPECT_FALSE(fs::exists(stale));
  EXPECT_TRUE(fs::exists(foreign / "data.txt"));
}

TEST_F(OutputFolderTest, SafeFileNamesStayInsideTheirFolder) {
  EXPECT_EQ(SafeFileName("suite_hilly_seed-3"), "suite_hilly_seed-3");
  EXPECT_EQ(SafeFileName("."), "_");
  EXPECT_EQ(SafeFileName(".."), "_.");
  EXPECT_EQ(SafeFileName(""), "_");
  EXPECT_EQ(SafeFileName("../../x"), "_.-..-x");
  EXPECT_EQ(SafeFileName("/abs/x"), "-abs-x");
  EXPECT_EQ(SafeFileName("a\nb c"), "a-b-c");
  const std::string long_name(300, 'n');
  const std::string safe = SafeFileName(long_name);
  EXPECT_EQ(safe.size(), 96u);
  EXPECT_NE(safe, SafeFileName(long_name + "m"));
}

TEST_F(OutputFolderTest, AFullDiskLeavesTheEarlierFileAndSaysWhy) {
  const fs::path file = root_ / "batch.json";
  WriteTextFileAtomically(file.string(), "{\"complete\": true}\n");
  // a file size limit stands for a full disk: writes past it fail with EFBIG
  const pid_t child = fork();
  if (child == 0) {
    signal(SIGXFSZ, SIG_IGN);
    const rlimit limit{8, 8};
    setrlimit(RLIMIT_FSIZE, &limit);
    try {
      WriteTextFileAtomically(file.string(), std::string(4096, 'x'));
    } catch (const common::InputError& e) {
      const std::string message = e.what();
      _exit(message.find("cannot write") != std::string::npos &&
                    message.find("batch.json") != std::string::npos
                ? 42
                : 1);
    }
    _exit(0);
  }
  int status = 0;
  waitpid(child, &status, 0);
  ASSERT_TRUE(WIFEXITED(status));
  EXPECT_EQ(WEXITSTATUS(status), 42) << "the failed write was not reported";
  EXPECT_EQ(test_util::ReadFile(file), "{\"complete\": true}\n");
  for (const auto& entry : fs::directory_iterator(root_)) {
    EXPECT_EQ(entry.path().filename(), "batch.json") << "left behind: " << entry.path();
  }
}

TEST_F(OutputFolderTest, ACampaignFolderIsUsedByOneProcessAtATime) {
  const fs::path out = root_ / "batch";
  {
    const CampaignFolder first(out.string(), "batch", "batch.json", {});
    EXPECT_EQ(FolderKindOf(out.string()), "batch");
    // a second process cannot open it while the first holds it
    const pid_t child = fork();
    if (child == 0) {
      try {
        const CampaignFolder second(out.string(), "batch", "batch.json", {});
      } catch (const common::InputError& e) {
        _exit(std::string(e.what()).find("in use") != std::string::npos ? 42 : 1);
      }
      _exit(0);
    }
    int status = 0;
    waitpid(child, &status, 0);
    EXPECT_EQ(WEXITSTATUS(status), 42);
  }
  // released with its owner; resumable; but no other kind and no folder of the user's
  EXPECT_NO_THROW(CampaignFolder(out.string(), "batch", "batch.json", {}));
  EXPECT_THROW(CampaignFolder(out.string(), "eval", "options.json", {}), common::InputError);
  Write(root_ / "mine" / "data.csv", "1,2");
  EXPECT_THROW(CampaignFolder((root_ / "mine").string(), "batch", "batch.json", {}),
               common::InputError);
  EXPECT_EQ(test_util::ReadFile(root_ / "mine" / "data.csv"), "1,2");
  // collecting needs a campaign that exists: nothing is created for a mistyped folder
  EXPECT_THROW(CampaignFolder((root_ / "typo").string(), "batch", "batch.json", {},
                              CampaignFolder::Use::kExisting),
               common::InputError);
  EXPECT_FALSE(fs::exists(root_ / "typo"));
  EXPECT_NO_THROW(
      CampaignFolder(out.string(), "batch", "batch.json", {}, CampaignFolder::Use::kExisting));
}

// What a killed process left half-written goes when the folder is opened again: in the folder
// itself (a report) and in the named subfolders, never elsewhere.
TEST_F(OutputFolderTest, ACampaignFolderRemovesHalfWrittenFiles) {
  const fs::path out = root_ / "campaign";
  { const CampaignFolder first(out.string(), "eval", "options.json", {"scenes"}); }
  fs::create_directories(out / "scenes");
  fs::create_directories(out / "logs");
  for (const fs::path& file : {out / "results.md.partial-99", out / "scenes" / "a.json.partial-7",
                               out / "logs" / "b.log.partial-5", out / "results.md"}) {
    std::ofstream(file) << "x";
  }
  const CampaignFolder again(out.string(), "eval", "options.json", {"scenes"});
  EXPECT_FALSE(fs::exists(out / "results.md.partial-99"));
  EXPECT_FALSE(fs::exists(out / "scenes" / "a.json.partial-7"));
  EXPECT_TRUE(fs::exists(out / "logs" / "b.log.partial-5"));  // not a subfolder it was told of
  EXPECT_TRUE(fs::exists(out / "results.md"));
}

TEST_F(OutputFolderTest, ACampaignFolderKeepsTheIdentityOfItsFirstCampaign) {
  const fs::path out = root_ / "campaign";
  const CampaignFolder folder(out.string(), "batch", "batch.json", {});
  auto same_runs = [](const nlohmann::json& mine) {
    return
        [mine](const nlohmann::json& previous) { return previous.at("runs") == mine.at("runs"); };
  };
  const nlohmann::json first = {{"runs", {1, 2}}, {"source", "a.yaml"}};
  folder.Claim(first, same_runs(first), "another batch");
  EXPECT_EQ(ReadJsonFile((out / "batch.json").string()), first);
  // the same runs from another file resume; the identity stays the first one's
  const nlohmann::json again = {{"runs", {1, 2}}, {"source", "b.yaml"}};
  EXPECT_NO_THROW(folder.Claim(again, same_runs(again), "another batch"));
  EXPECT_EQ(ReadJsonFile((out / "batch.json").string()), first);
  const nlohmann::json other = {{"runs", {3}}, {"source", "a.yaml"}};
  EXPECT_THAT([&] { folder.Claim(other, same_runs(other), "another batch"); },
              ::testing::ThrowsMessage<common::InputError>(
                  ::testing::AllOf(::testing::HasSubstr((out / "batch.json").string()),
                                   ::testing::HasSubstr("another batch"))));
}

}  // namespace
}  // namespace trav::scenarios
