/* The vertical model's matrices (docs/vertical.md, "Equations of motion"):
 * each element adds k J'J to K and c J'J to C for its elongation e = J q
 * (minus the track input), the bending mode its modal stiffness and damping. */
#include <math.h>
#include <string.h>
#include "railride/vertical.h"
#include "util/internal.h"

double rr_beam_shape(double x, double len)
{
  double beta = RR_BEAM_BETA_L / len, h = 0.5 * RR_BEAM_BETA_L;
  return -(cos(beta * x) / cos(h) + cosh(beta * x) / cosh(h));
}

double rr_vertical_phi(const rr_vertical_model *m, double x)
{
  return rr_beam_shape(x, m->carbody_length) / sqrt(m->carbody_mass);
}

void rr_vertical_floor_row(const rr_vertical_model *m, double x, double row[RR_VDOF])
{
  memset(row, 0, sizeof(double) * RR_VDOF);
  row[RR_V_ZC] = 1;
  row[RR_V_THC] = -x; /* u_z = z - x theta: positive pitch lowers the front */
  row[RR_V_QB] = rr_vertical_phi(m, x);
}

/* k J'J and c J'J of one element J (RR_VDOF) */
static void add_element(rr_vertical_model *m, const double *J, double k, double c)
{
  for (int i = 0; i < RR_VDOF; i++)
    for (int j = 0; j < RR_VDOF; j++) {
      m->K[i * RR_VDOF + j] += k * J[i] * J[j];
      m->C[i * RR_VDOF + j] += c * J[i] * J[j];
    }
}

static int check_layout(const rr_vehicle *v, rr_error *err)
{
  int st = rr_vehicle_check(v, err);
  if (st) return st;
  if (!(v->wheelbase_half < v->bogie_half_spacing))
    return rr_seterr(err, RR_EINVAL,
                     "[layout] wheelbase_half: b = %g m must be below bogie_half_spacing L = %g m",
                     v->wheelbase_half, v->bogie_half_spacing);
  if (!(v->bogie_half_spacing < 0.5 * v->carbody_length))
    return rr_seterr(err, RR_EINVAL,
                     "[carbody] length: the bogie pivots (+-%g m) must lie on the carbody "
                     "(length %g m)",
                     v->bogie_half_spacing, v->carbody_length);
  return RR_OK;
}

/* the secondary of bogie i (air springs at the frame centre) */
static void add_secondary(rr_vertical_model *m, int i, double ks, double cs)
{
  double J[RR_VDOF] = {0};
  int zf = i ? RR_V_ZF2 : RR_V_ZF1;
  J[RR_V_ZC] = 1;
  J[RR_V_THC] = -m->x_frames[i];
  J[RR_V_QB] = m->phi_pivots[i];
  J[zf] = -1;
  add_element(m, J, ks, cs);
}

/* the primary of wheelset j (2 boxes), and its input columns */
static void add_primary(rr_vertical_model *m, int j, double kp, double cp, double b)
{
  double J[RR_VDOF] = {0}, s = (j % 2 == 0) ? 1 : -1; /* leading axle of its bogie: +1 */
  int zf = j < 2 ? RR_V_ZF1 : RR_V_ZF2, th = zf + 1;
  J[zf] = 1;
  J[th] = -s * b;
  add_element(m, J, kp, cp);
  for (int d = 0; d < RR_VDOF; d++) {
    m->BK[d * RR_VINPUTS + j] = kp * J[d];
    m->BC[d * RR_VINPUTS + j] = cp * J[d];
  }
}

int rr_vertical_model_build(const rr_vehicle *v, rr_vertical_model *m, rr_error *err)
{
  int st = check_layout(v, err);
  if (st) return st;
  double L = v->bogie_half_spacing, b = v->wheelbase_half;
  double wb = 2 * RR_PI * v->carbody_bending_frequency;
  *m = (rr_vertical_model){.M = {v->carbody_mass, v->carbody_pitch_inertia, 1, v->frame_mass,
                                 v->frame_pitch_inertia, v->frame_mass, v->frame_pitch_inertia},
                           .x_frames = {L, -L},
                           .x_wheelsets = {L + b, L - b, -L + b, -L - b},
                           .carbody_length = v->carbody_length,
                           .carbody_mass = v->carbody_mass};
  for (int i = 0; i < 2; i++) m->phi_pivots[i] = rr_vertical_phi(m, m->x_frames[i]);
  for (int j = 0; j < RR_VINPUTS; j++) m->d_wheelsets[j] = m->x_wheelsets[0] - m->x_wheelsets[j];
  for (int i = 0; i < 2; i++) add_secondary(m, i, 2 * v->secondary_kz, 2 * v->secondary_cz);
  for (int j = 0; j < RR_VINPUTS; j++) add_primary(m, j, 2 * v->primary_kz, 2 * v->primary_cz, b);
  m->K[RR_V_QB * RR_VDOF + RR_V_QB] += wb * wb;
  m->C[RR_V_QB * RR_VDOF + RR_V_QB] += 2 * v->carbody_bending_damping * wb;
  return RR_OK;
}
