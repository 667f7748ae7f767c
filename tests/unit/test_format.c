/* Number formatting: shortest round trip, fixed digits, no negative zero. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "check.h"
#include "psim/psim.h"

int main(void)
{
    char buf[PSIM_FORMAT_MAX];
    psim_format_double(buf, 3.0, -1);
    CHECK(strcmp(buf, "3") == 0);
    psim_format_double(buf, 0.1, -1);
    CHECK(strcmp(buf, "0.1") == 0);
    psim_format_double(buf, 0.1 + 0.2, -1);
    CHECK(strcmp(buf, "0.30000000000000004") == 0);
    psim_format_double(buf, 1e-300, -1);
    CHECK(strtod(buf, NULL) == 1e-300);
    /* random doubles read back exactly */
    unsigned long long s = 88172645463325252ull;
    for (int k = 0; k < 20000; k++) {
        s ^= s << 13, s ^= s >> 7, s ^= s << 17;
        double v = ldexp((double)(s >> 11), (int)(s % 80) - 60) * ((s & 1) ? -1 : 1);
        int len = psim_format_double(buf, v, -1);
        CHECK_MSG(strtod(buf, NULL) == v, "%s", buf);
        CHECK(len == (int)strlen(buf) && len <= 24);
    }
    /* fixed digits */
    psim_format_double(buf, 1.5, 8);
    CHECK(strcmp(buf, "1.50000000") == 0);
    psim_format_double(buf, -0.0, 8);
    CHECK(strcmp(buf, "0.00000000") == 0);
    psim_format_double(buf, -1e-12, 8);
    CHECK(strcmp(buf, "0.00000000") == 0);
    psim_format_double(buf, -2e-8, 8);
    CHECK(strcmp(buf, "-0.00000002") == 0);
    psim_format_double(buf, -0.000000004, 3);
    CHECK(strcmp(buf, "0.000") == 0);
    psim_format_double(buf, -12.25, 1);
    CHECK(strcmp(buf, "-12.2") == 0 || strcmp(buf, "-12.3") == 0);
    /* the widest numbers fit whole */
    int len = psim_format_double(buf, -1.7976931348623157e308, PSIM_DIGITS_MAX);
    CHECK(len == 1 + 309 + 1 + PSIM_DIGITS_MAX && (int)strlen(buf) == len);
    CHECK(strtod(buf, NULL) == -1.7976931348623157e308);
    psim_format_double(buf, 1e60, 8);
    CHECK(strcmp(buf + strlen(buf) - 9, ".00000000") == 0);
    psim_format_double(buf, -4.9e-324, -1);
    CHECK(strtod(buf, NULL) == -4.9e-324);
    return check_done();
}
