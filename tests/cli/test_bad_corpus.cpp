// The bad-input corpus (issue 16): every scene under tests/data/bad/ (truncated and deeply
// nested JSON, wrong types, NaN/Inf numbers, negative sizes, huge counts, missing and
// unreadable files, OBJ with out-of-range and zero indices, empty and garbage OBJ, images that
// are not images and of zero bytes, unsupported textures and glTF, a film too large for the
// device) is run through the archwave binary as a user would, with the exit code and a message
// fragment its line of tests/data/bad/EXPECTED gives (and the extra arguments of its 4th column, if any). Each must fail with that code, name what
// is wrong, write nothing, never crash (no signal), and finish within 60 seconds.
#include <gtest/gtest.h>

#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

namespace {

namespace fs = std::filesystem;

struct Case {
  std::string file;
  int code;
  std::string fragment;
  std::string args;  // extra command-line arguments (4th column, optional)
};

std::vector<Case> read_expected(const std::string& dir) {
  std::vector<Case> cases;
  std::ifstream in(dir + "/EXPECTED");
  std::string line;
  while (std::getline(in, line)) {
    if (line.empty() || line[0] == '#') continue;
    std::istringstream s(line);
    Case c;
    std::string code;
    std::getline(s, c.file, '\t');
    std::getline(s, code, '\t');
    std::getline(s, c.fragment, '\t');
    std::getline(s, c.args);
    c.code = std::stoi(code);
    cases.push_back(c);
  }
  return cases;
}

TEST(BadCorpus, EveryFileFailsWithItsCodeAndMessageInTime) {
  const std::string dir = std::string(ARCHWAVE_SOURCE_DIR) + "/tests/data/bad";
  const std::vector<Case> cases = read_expected(dir);
  ASSERT_GE(cases.size(), 30u) << "the corpus holds at least 30 scenes";
  const std::string out_dir = testing::TempDir() + "/bad_corpus_" + std::to_string(getpid());
  fs::create_directories(out_dir);
  // Every scene in the folder is listed: a file added without its expectation is an error.
  size_t scenes = 0;
  for (const auto& e : fs::directory_iterator(dir)) scenes += e.path().extension() == ".json";
  EXPECT_EQ(scenes, cases.size()) << "every tests/data/bad/*.json has a line in EXPECTED";
  for (const Case& c : cases) {
    const std::string out = out_dir + "/" + c.file + ".exr", err = out_dir + "/stderr.txt";
    // timeout(1) bounds a hang; the corpus must never need it (124 would fail the code check).
    const std::string cmd = "timeout 60 " + std::string(ARCHWAVE_BINARY) + " " + dir + "/" + c.file + " -o " + out +
                            " -q --no-progress " + c.args + " 2>" + err + " >/dev/null";
    const auto t0 = std::chrono::steady_clock::now();
    const int status = std::system(cmd.c_str());
    const double secs = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    std::ifstream in(err);
    const std::string msg((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    ASSERT_TRUE(WIFEXITED(status)) << c.file << ": killed by a signal";
    const int code = WEXITSTATUS(status);
    EXPECT_EQ(code, c.code) << c.file << " (" << secs << " s): " << msg;
    EXPECT_NE(msg.find(c.fragment), std::string::npos) << c.file << ": expected \"" << c.fragment << "\" in: " << msg;
    EXPECT_FALSE(fs::exists(out)) << c.file << ": wrote an image";
    EXPECT_LT(secs, 60.0) << c.file;
    std::printf("%-36s exit %d  %5.2f s  %s", c.file.c_str(), code, secs, msg.c_str());
  }
}

}  // namespace
