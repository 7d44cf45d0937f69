// The fuzz harnesses without libFuzzer (any C++ compiler, e.g. the normal gcc
// build): run LLVMFuzzerTestOneInput on every file named (a folder: every file
// in it), then, with --mutate N, on N mutants of each (bytes flipped,
// inserted, deleted, copied from another input; a fixed seed, so a failure
// repeats). A violated invariant aborts, as under libFuzzer.
//   replay [--mutate N] [--seed S] PATH...
#include <dirent.h>
#include <sys/stat.h>

#include <algorithm>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <iterator>
#include <random>
#include <string>
#include <vector>

extern "C" int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);

namespace {

using Bytes = std::vector<uint8_t>;

bool is_dir(const std::string &p)
{
    struct stat st;
    return stat(p.c_str(), &st) == 0 && S_ISDIR(st.st_mode);
}

void collect(const std::string &path, std::vector<std::string> &out)
{
    if (!is_dir(path)) {
        out.push_back(path);
        return;
    }
    DIR *d = opendir(path.c_str());
    if (d == nullptr)
        return;
    std::vector<std::string> names;
    while (dirent *e = readdir(d))
        if (e->d_name[0] != '.')
            names.push_back(path + "/" + e->d_name);
    closedir(d);
    std::sort(names.begin(), names.end()); // the same order everywhere
    for (const auto &n : names)
        collect(n, out);
}

Bytes read_all(const std::string &path)
{
    std::ifstream f(path, std::ios::binary);
    return Bytes((std::istreambuf_iterator<char>(f)), std::istreambuf_iterator<char>());
}

Bytes mutate(const Bytes &in, const std::vector<Bytes> &all, std::mt19937 &rng)
{
    Bytes b = in;
    int edits = 1 + int(rng() % 8);
    for (int k = 0; k < edits; k++) {
        size_t n = b.size();
        switch (rng() % 6) {
        case 0: // flip a bit
            if (n > 0)
                b[rng() % n] ^= uint8_t(1u << (rng() % 8));
            break;
        case 1: // a random byte
            if (n > 0)
                b[rng() % n] = uint8_t(rng());
            break;
        case 2: // insert bytes
            b.insert(b.begin() + long(n > 0 ? rng() % (n + 1) : 0), size_t(1 + rng() % 4), uint8_t(rng()));
            break;
        case 3: // delete a run
            if (n > 0) {
                size_t at = rng() % n, len = std::min<size_t>(n - at, 1 + rng() % 8);
                b.erase(b.begin() + long(at), b.begin() + long(at + len));
            }
            break;
        case 4: { // splice a piece of another input
            const Bytes &o = all[rng() % all.size()];
            if (!o.empty()) {
                size_t from = rng() % o.size(), len = std::min<size_t>(o.size() - from, 1 + rng() % 32);
                size_t at = n > 0 ? rng() % (n + 1) : 0;
                b.insert(b.begin() + long(at), o.begin() + long(from), o.begin() + long(from + len));
            }
            break;
        }
        default: // an interesting byte
            if (n > 0) {
                static const uint8_t v[] = {0x00, 0x01, 0x7F, 0x80, 0xFF, '0', '=', '\n', '[', ']', '.', '-'};
                b[rng() % n] = v[rng() % sizeof v];
            }
            break;
        }
    }
    return b;
}

} // namespace

int main(int argc, char **argv)
{
    long mutants = 0;
    unsigned seed = 12345;
    std::vector<std::string> files;
    for (int i = 1; i < argc; i++) {
        if (std::strcmp(argv[i], "--mutate") == 0 && i + 1 < argc)
            mutants = std::strtol(argv[++i], nullptr, 10);
        else if (std::strcmp(argv[i], "--seed") == 0 && i + 1 < argc)
            seed = unsigned(std::strtoul(argv[++i], nullptr, 10));
        else
            collect(argv[i], files);
    }
    if (files.empty()) {
        std::fprintf(stderr, "usage: %s [--mutate N] [--seed S] PATH...\n", argv[0]);
        return 2;
    }
    std::vector<Bytes> inputs;
    for (const auto &f : files)
        inputs.push_back(read_all(f));
    long runs = 0;
    for (const Bytes &b : inputs) {
        LLVMFuzzerTestOneInput(b.data(), b.size());
        runs++;
    }
    std::mt19937 rng(seed);
    for (const Bytes &b : inputs)
        for (long k = 0; k < mutants; k++) {
            Bytes m = mutate(b, inputs, rng);
            LLVMFuzzerTestOneInput(m.data(), m.size());
            runs++;
        }
    std::printf("%s: %zu inputs, %ld runs, no invariant violated\n", argv[0], inputs.size(), runs);
    return 0;
}
