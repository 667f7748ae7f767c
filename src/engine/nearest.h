/* The nearest pair of the sorted store: a lower bound on every pair's
 * distance, for models that leave out work no pair can need for a while
 * (the ccd model's free flight, the force model's list lifetime). */
#ifndef PSIM_ENGINE_NEAREST_H
#define PSIM_ENGINE_NEAREST_H
#include "engine.h"

/* The smallest squared distance above `above2` (-1: any) between two
 * particles in the same or adjacent cells of e's grid, or INFINITY where
 * there is none; pairs in cells further apart are at least e->grid.h
 * apart, so min(sqrt(result), h) bounds every pair beyond above2.  Needs
 * the store sorted by cell for the current positions.  A minimum, so the
 * result does not depend on the thread count; NaN positions are in no
 * comparison and are left out. */
double psim_nearest2(const psim_sim *e, double above2);

#endif
