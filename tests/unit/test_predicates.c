/* The course's collision predicates and resolutions. */
#include <math.h>

#include "check.h"
#include "models/discrete/collide.h"

static void test_walls(void)
{
    const double L = 10, r = 1;
    /* touching the left wall and moving left: a collision */
    CHECK(psim_wall_collides(1.0, 5, -1, 0, L, r));
    /* touching but moving away or still: none */
    CHECK(!psim_wall_collides(1.0, 5, 1, 0, L, r));
    CHECK(!psim_wall_collides(1.0, 5, 0, 0, L, r));
    /* just inside: none */
    CHECK(!psim_wall_collides(1.0 + 1e-12, 5, -1, 0, L, r));
    /* right, bottom, top */
    CHECK(psim_wall_collides(9.0, 5, 0.5, 0, L, r));
    CHECK(psim_wall_collides(5, 1.0, 0, -2, L, r));
    CHECK(psim_wall_collides(5, 9.0, 0, 2, L, r));
    /* outside the box entirely (positions are never clamped) */
    CHECK(psim_wall_collides(-3, 5, -1, 0, L, r));
    CHECK(psim_wall_collides(15, 5, 1, 0, L, r));

    double vx = -2, vy = 3;
    psim_wall_resolve(0.5, 5, &vx, &vy, L, r);
    CHECK(vx == 2 && vy == 3);
    vx = 4, vy = 3;
    psim_wall_resolve(9.5, 9.5, &vx, &vy, L, r);
    CHECK(vx == -4 && vy == -3);
    /* corner: both flip */
    vx = -1, vy = -1;
    psim_wall_resolve(0.5, 0.5, &vx, &vy, L, r);
    CHECK(vx == 1 && vy == 1);
    /* the course sets |v| at a wall even for the axis that did not collide */
    vx = 1, vy = -0.0;
    psim_wall_resolve(0.5, 0.5, &vx, &vy, L, r);
    CHECK(vx == 1 && !signbit(vy));
}

static void test_pairs(void)
{
    const double four_r2 = 4.0; /* r = 1 */
    CHECK(psim_overlaps(4.0, four_r2));          /* touching counts */
    CHECK(psim_overlaps(3.9, four_r2));
    CHECK(!psim_overlaps(4.0000001, four_r2));
    /* head-on: p1 = (0,0) v1 = (1,0); p2 = (1.5,0) v2 = (-1,0) */
    double dx = 1.5, dy = 0, dot = psim_approach(dx, dy, -1 - 1, 0 - 0);
    CHECK(dot == -3.0);
    CHECK(psim_moving_closer(dot));
    /* the threshold is strict at -1e-7 */
    CHECK(!psim_moving_closer(-1e-7));
    CHECK(psim_moving_closer(-1.0000001e-7));
    CHECK(!psim_moving_closer(0.0));

    double vx1 = 1, vy1 = 0, vx2 = -1, vy2 = 0;
    psim_pair_resolve(dot, dx, dy, dx * dx + dy * dy, &vx1, &vy1, &vx2, &vy2);
    /* equal masses, head-on: velocities exchange */
    CHECK(vx1 == -1 && vx2 == 1 && vy1 == 0 && vy2 == 0);
    /* after resolution they separate: dv.dp = +3 */
    CHECK(psim_approach(dx, dy, vx2 - vx1, vy2 - vy1) == 3.0);

    /* oblique: only the normal component is exchanged, momentum and energy
     * are conserved */
    double ax = 0.3, ay = -0.2, bx = -0.5, by = 0.4;
    double px = 1.2, py = 1.1, d2 = px * px + py * py;
    double e0 = ax * ax + ay * ay + bx * bx + by * by, m0x = ax + bx, m0y = ay + by;
    double tang0 = (bx - ax) * -py + (by - ay) * px;
    double d = psim_approach(px, py, bx - ax, by - ay);
    CHECK(psim_moving_closer(d));
    psim_pair_resolve(d, px, py, d2, &ax, &ay, &bx, &by);
    double e1 = ax * ax + ay * ay + bx * bx + by * by;
    CHECK(fabs(e1 - e0) < 1e-15);
    CHECK(fabs(ax + bx - m0x) < 1e-15 && fabs(ay + by - m0y) < 1e-15);
    CHECK(fabs(psim_approach(px, py, bx - ax, by - ay) + d) < 1e-15);
    CHECK(fabs((bx - ax) * -py + (by - ay) * px - tang0) < 1e-15);
}

int main(void)
{
    test_walls();
    test_pairs();
    return check_done();
}
