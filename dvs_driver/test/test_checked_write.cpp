// Checked writes (checked_write.h, checked_bag.h) and the tools that use them: a full disk (a
// symlink to /dev/full, or a file size limit part way through), a missing folder, a folder as
// the output: a WriteError / BagWriteError naming the file and the OS reason, never an abort,
// never a file under the real name that is not complete.
#include <dvs_driver/checked_bag.h>
#include <dvs_driver/checked_write.h>
#include <dvs_driver/event_bag_io.h>
#include <dvs_driver/event_text_io.h>
#include <gtest/gtest.h>

#include <csignal>
#include <fstream>
#include <functional>
#include <sstream>
#include <string>
#include <sys/resource.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

namespace
{
std::string tempDir()
{
  static std::string dir;
  if (dir.empty())
  {
    char tmpl[] = "/tmp/dvs_checked_write_XXXXXX";
    dir = ::mkdtemp(tmpl);
  }
  return dir;
}

std::string fullLink(const std::string& name)
{
  const std::string p = tempDir() + "/" + name;
  ::unlink(p.c_str());
  EXPECT_EQ(0, ::symlink("/dev/full", p.c_str()));
  return p;
}

bool exists(const std::string& p)
{
  struct stat st;
  return ::lstat(p.c_str(), &st) == 0;
}

std::string readAll(const std::string& p)
{
  std::ifstream in(p, std::ios::binary);
  std::ostringstream s;
  s << in.rdbuf();
  return s.str();
}

template <class E>
std::string errorOf(const std::function<void()>& f)
{
  try
  {
    f();
  }
  catch (const E& e)
  {
    return e.what();
  }
  return "(no error)";
}

dvs_driver::EventStream someEvents(size_t n)
{
  dvs_driver::EventStream s;
  s.width = s.height = 128;
  for (size_t i = 0; i < n; ++i)
    s.events.push_back(dvs_driver::Event{static_cast<int64_t>(1000000 + i * 1000), static_cast<uint16_t>(i % 128),
                                         static_cast<uint16_t>((i / 128) % 128), (i & 1) != 0});
  return s;
}

// Runs f in a child process whose files may not grow beyond `limit` bytes (a disk that fills up
// part way through: writes fail with EFBIG); returns the child's exit status (-signal if killed).
int inChildWithFileLimit(rlim_t limit, const std::function<int()>& f)
{
  const pid_t pid = ::fork();
  if (pid == 0)
  {
    std::signal(SIGXFSZ, SIG_IGN);
    struct rlimit rl = {limit, limit};
    ::setrlimit(RLIMIT_FSIZE, &rl);
    ::_exit(f());
  }
  int st = 0;
  ::waitpid(pid, &st, 0);
  return WIFEXITED(st) ? WEXITSTATUS(st) : -WTERMSIG(st);
}
}  // namespace

TEST(CheckedWrite, WritesAndReplacesAtomically)
{
  const std::string p = tempDir() + "/a.txt";
  dvs_driver::writeFileChecked(p, std::string("first\n"));
  EXPECT_EQ("first\n", readAll(p));
  dvs_driver::writeFileChecked(p, [](std::ostream& out) { out << "second " << 2 << "\n"; });
  EXPECT_EQ("second 2\n", readAll(p));
  EXPECT_FALSE(exists(p + ".tmp"));
  // An exception while filling leaves the old file as it was and no temporary file.
  EXPECT_THROW(dvs_driver::writeFileChecked(p, [](std::ostream& out) {
                 out << "partial";
                 throw std::runtime_error("stop");
               }),
               std::runtime_error);
  EXPECT_EQ("second 2\n", readAll(p));
  EXPECT_FALSE(exists(p + ".tmp"));
  // A symlink to a regular file: the target is replaced, the link stays.
  const std::string link = tempDir() + "/link.txt";
  ::unlink(link.c_str());
  ASSERT_EQ(0, ::symlink(p.c_str(), link.c_str()));
  dvs_driver::writeFileChecked(link, std::string("third\n"));
  EXPECT_EQ("third\n", readAll(p));
  struct stat st;
  ASSERT_EQ(0, ::lstat(link.c_str(), &st));
  EXPECT_TRUE(S_ISLNK(st.st_mode));
  // A device is written directly.
  dvs_driver::writeFileChecked("/dev/null", std::string("gone\n"));
}

TEST(CheckedWrite, FullDiskNamesTheFileAndTheReason)
{
  const std::string p = fullLink("full.txt");
  const std::string err = errorOf<dvs_driver::WriteError>([&] {
    dvs_driver::CheckedFileWriter w(p);
    for (int i = 0; i < 100000; ++i)
      w.stream() << "line " << i << "\n";
    w.commit();
  });
  EXPECT_NE(std::string::npos, err.find(p + ": write failed: No space left on device")) << err;
  // Small writes only fail at the flush in commit().
  const std::string small = errorOf<dvs_driver::WriteError>([&] { dvs_driver::writeFileChecked(p, std::string("x")); });
  EXPECT_NE(std::string::npos, small.find("No space left on device")) << small;
  // The events.txt writer uses it.
  const std::string ev = errorOf<dvs_driver::WriteError>([&] { dvs_driver::writeEventsText(p, someEvents(10).events); });
  EXPECT_NE(std::string::npos, ev.find(p + ": write failed: No space left on device")) << ev;
}

TEST(CheckedWrite, MissingFolderAndFolderAsFile)
{
  const std::string p = tempDir() + "/no/such/folder/out.txt";
  const std::string err = errorOf<dvs_driver::WriteError>([&] { dvs_driver::writeFileChecked(p, std::string("x")); });
  EXPECT_NE(std::string::npos, err.find(p + ": cannot create the file: No such file or directory")) << err;
  EXPECT_NE(std::string::npos, err.find("the folder `" + tempDir() + "/no/such/folder` does not exist")) << err;
  const std::string dir = errorOf<dvs_driver::WriteError>([&] { dvs_driver::writeFileChecked(tempDir(), std::string("x")); });
  EXPECT_NE(std::string::npos, dir.find("Is a directory")) << dir;
  EXPECT_THROW(dvs_driver::writeEventsText(p, someEvents(3).events), dvs_driver::WriteError);
}

TEST(CheckedWrite, DiskFullingUpPartWayThrough)
{
  // The file may not grow beyond 64 KiB: a write part way through fails (EFBIG).
  const std::string p = tempDir() + "/limited.txt";
  const int status = inChildWithFileLimit(65536, [&] {
    try
    {
      dvs_driver::writeEventsText(p, someEvents(100000).events);
    }
    catch (const dvs_driver::WriteError& e)
    {
      return std::string(e.what()).find(p + ": write failed: File too large") != std::string::npos ? 3 : 4;
    }
    return 5;
  });
  EXPECT_EQ(3, status);
  EXPECT_FALSE(exists(p));  // nothing incomplete under the real name
  EXPECT_FALSE(exists(p + ".tmp"));
}

TEST(CheckedBag, RoundTripAndNamedErrors)
{
  const dvs_driver::EventStream s = someEvents(5000);
  const std::string p = tempDir() + "/ok.bag";
  EXPECT_EQ(5u, dvs_driver::writeEventsBag(p, "/dvs/events", s));
  EXPECT_FALSE(exists(p + ".tmp"));
  const dvs_driver::EventStream back = dvs_driver::readEventsBag(p);
  ASSERT_EQ(s.events.size(), back.events.size());
  EXPECT_EQ(s.events.back(), back.events.back());

  // Full disk (a link to /dev/full): the finished bag cannot be copied into it.
  const std::string full = fullLink("full.bag");
  std::string err = errorOf<dvs_driver::BagWriteError>([&] { dvs_driver::writeEventsBag(full, "/dvs/events", s); });
  EXPECT_NE(std::string::npos, err.find(full + ": write failed: No space left on device")) << err;
  // rosbag's own file on a full disk: its BagIOException becomes a BagWriteError (no abort).
  const std::string p2 = tempDir() + "/rosbag_full.bag";
  fullLink("rosbag_full.bag.tmp");
  err = errorOf<dvs_driver::BagWriteError>([&] { dvs_driver::writeEventsBag(p2, "/dvs/events", s); });
  EXPECT_NE(std::string::npos, err.find(p2 + ": cannot create the bag: Error writing to file")) << err;
  EXPECT_NE(std::string::npos, err.find("No space left on device")) << err;
  EXPECT_FALSE(exists(p2));
  // Missing folder.
  const std::string missing = tempDir() + "/nope/x.bag";
  err = errorOf<dvs_driver::BagWriteError>([&] { dvs_driver::writeEventsBag(missing, "/dvs/events", s); });
  EXPECT_NE(std::string::npos, err.find(missing + ": cannot create the bag")) << err;
  EXPECT_NE(std::string::npos, err.find("does not exist")) << err;
  // A non-rosbag error inside run() propagates unchanged and the bag stays usable.
  dvs_driver::CheckedBagWriter bag(tempDir() + "/mixed.bag");
  dvs_driver::EventVector backwards = {{2000, 1, 1, true}, {1000, 1, 1, true}};
  EXPECT_THROW(dvs_driver::writeEventsBag(bag, "/dvs/events", backwards, 128, 128), dvs_driver::EventBagError);
  EXPECT_EQ(5u, dvs_driver::writeEventsBag(bag, "/dvs/events", s.events, 128, 128));
  bag.close();
  EXPECT_EQ(s.events.size(), dvs_driver::readEventsBag(tempDir() + "/mixed.bag").events.size());
}

TEST(CheckedBag, DiskFillingUpWhileWritingGivesANamedErrorNotAnAbort)
{
  // rosbag's writes fail part way through (file size limit): every failure is a BagWriteError,
  // whether in write() or in close(); the process does not abort.
  for (const rlim_t limit : {rlim_t(8192), rlim_t(200000), rlim_t(1500000)})
  {
    const std::string p = tempDir() + "/limited_" + std::to_string(limit) + ".bag";
    const int status = inChildWithFileLimit(limit, [&] {
      try
      {
        dvs_driver::writeEventsBag(p, "/dvs/events", someEvents(200000));
      }
      catch (const dvs_driver::BagWriteError& e)
      {
        return std::string(e.what()).find(p + ": ") == 0 ? 3 : 4;
      }
      return 5;
    });
    EXPECT_EQ(3, status) << "limit " << limit;
    EXPECT_FALSE(exists(p)) << limit;
    EXPECT_FALSE(exists(p + ".tmp")) << limit;
  }
}
