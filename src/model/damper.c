/* Maxwell damper characteristics (paper eq. 3-8): a damper c in series with a
 * spring k has dynamic stiffness k c jw / (k + c jw). */
#include <math.h>
#include "railride/damper.h"
#include "util/internal.h"

double complex rr_maxwell_stiffness(double complex k, double c, double complex s)
{
  if (isinf(creal(k))) return c * s;
  return k * c * s / (k + c * s);
}

rr_damper_point rr_maxwell_point(double k, double c, double f_hz)
{
  double w = 2 * RR_PI * f_hz;
  double complex ke = rr_maxwell_stiffness(k, c, I * w);
  rr_damper_point p;
  p.freq_hz = f_hz;
  p.storage = creal(ke);
  p.loss = cimag(ke);
  p.eq_damping = w > 0 ? p.loss / w : c;
  p.dissipation = p.storage > 0 ? p.loss / p.storage : INFINITY;
  return p;
}

double rr_maxwell_omega_opt(double k, double c) { return k / c; }
