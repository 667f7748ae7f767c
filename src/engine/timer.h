/* Wall-clock timers around phases (CoMD's performanceTimers, in small). */
#ifndef PSIM_ENGINE_TIMER_H
#define PSIM_ENGINE_TIMER_H

double psim_now(void); /* seconds, monotonic */

#endif
