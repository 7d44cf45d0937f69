// Temporary directories and whole-file reads and writes for tests, with no
// project library behind them, so a test of one layer can use them and still
// link that layer alone.
#pragma once

#include <cstdlib>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

namespace simtest {

// A fresh directory under the system temp dir, removed by the destructor.
class TempDir {
public:
    TempDir()
    {
        std::string tmpl = "/tmp/dtc_test_XXXXXX";
        std::vector<char> buf(tmpl.begin(), tmpl.end());
        buf.push_back('\0');
        const char *p = mkdtemp(buf.data());
        path_ = p != nullptr ? p : "/tmp";
    }
    ~TempDir()
    {
        if (path_ != "/tmp")
            std::system(("rm -rf '" + path_ + "'").c_str());
    }
    TempDir(const TempDir &) = delete;
    TempDir &operator=(const TempDir &) = delete;
    std::string file(const std::string &name) const { return path_ + "/" + name; }
    const std::string &path() const { return path_; }

private:
    std::string path_;
};

inline void write_file(const std::string &path, const std::string &text)
{
    std::ofstream f(path, std::ios::binary);
    f << text;
}

inline bool file_exists(const std::string &path)
{
    std::ifstream f(path);
    return f.good();
}

inline std::string read_file(const std::string &path)
{
    std::ifstream f(path, std::ios::binary);
    std::stringstream ss;
    ss << f.rdbuf();
    return ss.str();
}

} // namespace simtest
