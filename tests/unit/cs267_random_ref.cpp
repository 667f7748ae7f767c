// The reference for tests/unit/test_cs267_random.c: the same draws made by
// the real std::mt19937 and libstdc++ distributions, printed in the format
// that `test_cs267_random dump` prints from psim's C versions
// (src/io/cs267_random.c); tests/unit/cs267_random_vs_cxx.sh compares the
// two outputs byte for byte.  Built with g++ -O2.
#include <climits>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <random>
#include <vector>

static const std::uint32_t seeds[] = {0u, 1u, 42u, 5489u, 4294967295u};
static const int int_ranges[][2] = {
    {0, 0}, {0, 1}, {0, 999}, {0, 2147483646}, {-5, 5},
    {-1000, -1}, {INT_MIN, (1 << 30) - 1}, {INT_MIN, INT_MAX}};
static const float real_ranges[][2] = {{-1.0f, 1.0f}, {0.0f, 1.0f}, {-2.5f, 7.0f}};
static const std::uint32_t edge_u[] = {
    0u, 1u, 127u, 128u, 255u, 256u, 0x7fffffffu, 0x80000000u, 0xffffff7fu,
    0xffffff80u, 0xfffffffeu, 0xffffffffu};
static const int place_n[] = {1, 2, 7, 1000};
enum { DRAWS = 50 };

// A generator with mt19937's range that returns one fixed value.
struct fixed_gen {
    typedef std::uint_fast32_t result_type;
    result_type v;
    static constexpr result_type min() { return 0; }
    static constexpr result_type max() { return 0xffffffffu; }
    result_type operator()() { return v; }
};

// init_particles of the course (CS267 HW2, 2020+), seeded directly.
static void place(int num_parts, double size, std::uint32_t seed,
                  std::vector<double>& x, std::vector<double>& y,
                  std::vector<double>& vx, std::vector<double>& vy)
{
    std::mt19937 gen(seed);
    int sx = (int)ceil(sqrt((double)num_parts));
    int sy = (num_parts + sx - 1) / sx;
    std::vector<int> shuffle(num_parts);
    for (int i = 0; i < num_parts; ++i)
        shuffle[i] = i;
    for (int i = 0; i < num_parts; ++i) {
        std::uniform_int_distribution<int> rand_int(0, num_parts - i - 1);
        int j = rand_int(gen);
        int k = shuffle[j];
        shuffle[j] = shuffle[num_parts - i - 1];
        x[i] = size * (1. + (k % sx)) / (1 + sx);
        y[i] = size * (1. + (k / sx)) / (1 + sy);
        std::uniform_real_distribution<float> rand_real(-1.0, 1.0);
        vx[i] = rand_real(gen);
        vy[i] = rand_real(gen);
    }
}

int main()
{
    for (std::uint32_t s : seeds) {
        std::mt19937 g(s);
        std::printf("mt19937 %u\n", (unsigned)s);
        for (int i = 0; i < DRAWS; i++)
            std::printf("%u\n", (unsigned)g());
    }
    for (std::uint32_t s : seeds)
        for (const auto& r : int_ranges) {
            std::mt19937 g(s);
            std::uniform_int_distribution<int> d(r[0], r[1]);
            std::printf("int %u %d %d\n", (unsigned)s, r[0], r[1]);
            for (int i = 0; i < DRAWS; i++)
                std::printf("%d\n", d(g));
            std::printf("next %u\n", (unsigned)g());
        }
    for (std::uint32_t s : seeds)
        for (const auto& r : real_ranges) {
            std::mt19937 g(s);
            std::uniform_real_distribution<float> d(r[0], r[1]);
            std::printf("real %u %a %a\n", (unsigned)s, (double)r[0], (double)r[1]);
            for (int i = 0; i < DRAWS; i++) {
                float v = d(g);
                std::printf("%a %.9g\n", (double)v, (double)v);
            }
        }
    for (std::uint32_t u : edge_u) {
        fixed_gen g{u};
        float c = std::generate_canonical<float, 24>(g);
        std::uniform_real_distribution<float> d(-1.0, 1.0);
        float v = d(g);
        std::printf("canonical %u %a %a\n", (unsigned)u, (double)c, (double)v);
    }
    for (std::uint32_t s : seeds)
        for (int n : place_n) {
            double size = sqrt(0.0005 * n);
            std::vector<double> x(n), y(n), vx(n), vy(n);
            place(n, size, s, x, y, vx, vy);
            std::printf("place %d %u %.17g\n", n, (unsigned)s, size);
            for (int i = 0; i < n; i++)
                std::printf("%d %.17g %.17g %.17g %.17g\n", i, x[i], y[i], vx[i], vy[i]);
        }
    return 0;
}
