/* The tread law lambda(a) for the stages after the vehicle (profile.c). */
#ifndef RR_PROFILE_IMPL_H
#define RR_PROFILE_IMPL_H
#include "railride/vehicle.h"

/* lambda(a) at amplitude a_m (m) and d lambda / da (per m) into *dlam_da. */
double rr_profile_eval(const rr_profile *p, double a_m, double *dlam_da);
#endif
