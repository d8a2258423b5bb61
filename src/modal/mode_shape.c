/* What a mode shape says: kinetic-energy shares per body group and in roll,
 * and a name by dominant motion ("carbody lateral-yaw", "frames roll,
 * anti-phase", "carbody lower sway"), as engineers read shapes in SIMPACK or
 * VAMPIRE. All from the q part of the eigenvector: the kinetic energy of DOF
 * i is 0.5 |lambda|^2 m_i |phi_i|^2, and the |lambda|^2 cancels in shares. */
#include <math.h>
#include <stdio.h>
#include <string.h>
#include "modal/modal_impl.h"

enum { MOT_Y, MOT_PSI, MOT_PHI, NMOT };
#define SHARE_SUBJECT 0.75 /* one body carries this much of its group: named alone */
#define SHARE_MOTION 0.2   /* a motion with this much of the subject's energy is named */
#define PHASE_COS 0.5      /* |cos| of the phase between two bodies to call it in/anti-phase */

static const char *group_one[RR_NGROUPS] = {"carbody", "frame", "wheelset"};
static const char *group_many[RR_NGROUPS] = {"carbodies", "frames", "wheelsets"};
static const char *motion_word[NMOT] = {"lateral", "yaw", "roll"};

static double dof_energy(const rr_model *m, const double complex *phi, int i)
{
  return i < 0 ? 0 : m->mdiag[i] * creal(phi[i] * conj(phi[i]));
}

static int body_dof(const rr_body *b, int mot)
{
  return mot == MOT_Y ? b->dof_y : mot == MOT_PSI ? b->dof_psi : b->dof_phi;
}

void rr_shape_normalise(double complex *phi, int n)
{
  double nrm = 0, big = 0;
  int ib = 0;
  for (int i = 0; i < n; i++) {
    double a = cabs(phi[i]);
    nrm += a * a;
    if (a > big) {
      big = a;
      ib = i;
    }
  }
  if (!(nrm > 0)) return;
  double complex sc = conj(phi[ib]) / (cabs(phi[ib]) * sqrt(nrm));
  for (int i = 0; i < n; i++) phi[i] *= sc;
}

/* "lower sway" when the roll centre lies below the body's reference point
   (u_y = y - dz phi vanishes at dz = y / phi), "upper sway" above. */
static const char *sway(const rr_body *b, const double complex *phi)
{
  double complex y = phi[b->dof_y], r = phi[b->dof_phi];
  double dz = creal(y * conj(r)) / creal(r * conj(r));
  return dz < 0 ? "lower sway" : "upper sway";
}

static void phase_suffix(const rr_model *m, const int *bodies, int mot, const double complex *phi,
                         char *buf, size_t len)
{
  int i = body_dof(&m->bodies[bodies[0]], mot), j = body_dof(&m->bodies[bodies[1]], mot);
  if (i < 0 || j < 0) return;
  double den = cabs(phi[i]) * cabs(phi[j]);
  if (!(den > 0)) return;
  double c = creal(phi[i] * conj(phi[j])) / den;
  if (fabs(c) >= PHASE_COS) snprintf(buf, len, ", %s", c > 0 ? "in phase" : "anti-phase");
}

typedef struct subject {
  char word[32];
  int bodies[RR_SYS_MAX_BODIES], nb; /* the bodies whose motion is named */
  int pair[2], npair;                /* two units to compare in phase (frames) */
} subject;

static double body_energy(const rr_model *m, const double complex *phi, int b)
{
  double e = 0;
  for (int mot = 0; mot < NMOT; mot++) e += dof_energy(m, phi, body_dof(&m->bodies[b], mot));
  return e;
}

/* The frame a wheelset rides in: the nearest in x. */
static int frame_of(const rr_model *m, int w)
{
  int best = -1;
  double d = INFINITY;
  for (int b = 0; b < m->nbodies; b++)
    if (m->bodies[b].group == RR_GROUP_FRAME &&
        fabs(m->bodies[b].ref[0] - m->bodies[w].ref[0]) < d) {
      d = fabs(m->bodies[b].ref[0] - m->bodies[w].ref[0]);
      best = b;
    }
  return best;
}

/* A bogie (frame and its wheelsets) when frames and wheelsets share the mode. */
static int bogie_subject(const rr_model *m, const double complex *phi, const double *eg, subject *s)
{
  double fw = eg[RR_GROUP_FRAME] + eg[RR_GROUP_WHEELSET];
  if (!(fw > eg[RR_GROUP_CARBODY]) || fmin(eg[RR_GROUP_FRAME], eg[RR_GROUP_WHEELSET]) < 0.25 * fw)
    return 0;
  int frames[RR_SYS_MAX_BODIES], nf = 0, top = 0;
  double eb[RR_SYS_MAX_BODIES] = {0};
  for (int b = 0; b < m->nbodies; b++)
    if (m->bodies[b].group == RR_GROUP_FRAME) {
      eb[nf] = body_energy(m, phi, b);
      frames[nf++] = b;
    }
  for (int b = 0; b < m->nbodies; b++) {
    if (m->bodies[b].group != RR_GROUP_WHEELSET) continue;
    int f = frame_of(m, b);
    for (int k = 0; k < nf; k++)
      if (frames[k] == f) eb[k] += body_energy(m, phi, b);
  }
  for (int k = 1; k < nf; k++)
    if (eb[k] > eb[top]) top = k;
  int alone = nf == 1 || eb[top] >= SHARE_SUBJECT * fw;
  if (alone && nf > 1)
    snprintf(s->word, sizeof s->word, "bogie %d", top + 1);
  else
    snprintf(s->word, sizeof s->word, alone ? "bogie" : "bogies");
  s->nb = 0;
  for (int b = 0; b < m->nbodies; b++) {
    int g = m->bodies[b].group, f = g == RR_GROUP_WHEELSET ? frame_of(m, b) : b;
    if (g != RR_GROUP_CARBODY && (!alone || f == frames[top])) s->bodies[s->nb++] = b;
  }
  s->npair = !alone && nf == 2 ? 2 : 0;
  s->pair[0] = frames[0];
  s->pair[1] = frames[nf > 1 ? 1 : 0];
  return 1;
}

/* The dominant group's body, or the group as a whole. */
static void group_subject(const rr_model *m, const double complex *phi, const double *eg,
                          subject *s)
{
  int g = 0;
  for (int k = 1; k < RR_NGROUPS; k++)
    if (eg[k] > eg[g]) g = k;
  int members[RR_SYS_MAX_BODIES], nb = 0, top = -1, ordinal = 0;
  double etop = -1;
  for (int b = 0; b < m->nbodies; b++) {
    if (m->bodies[b].group != g) continue;
    double e = body_energy(m, phi, b);
    members[nb++] = b;
    if (e > etop) {
      etop = e;
      top = b;
      ordinal = nb;
    }
  }
  int alone = nb == 1 || etop >= SHARE_SUBJECT * eg[g];
  if (alone && nb == 1)
    snprintf(s->word, sizeof s->word, "%s", group_one[g]);
  else if (alone)
    snprintf(s->word, sizeof s->word, "%s %d", group_one[g], ordinal);
  else
    snprintf(s->word, sizeof s->word, "%s", group_many[g]);
  s->nb = 0;
  for (int k = 0; k < nb; k++)
    if (!alone || members[k] == top) s->bodies[s->nb++] = members[k];
  s->npair = !alone && nb == 2 ? 2 : 0;
  s->pair[0] = members[0];
  s->pair[1] = members[nb > 1 ? 1 : 0];
}

static void name_mode(const rr_model *m, const double complex *phi, const double *eg, char *buf,
                      size_t len)
{
  subject s;
  if (!bogie_subject(m, phi, eg, &s)) group_subject(m, phi, eg, &s);
  double emot[NMOT] = {0, 0, 0}, esub = 0;
  for (int k = 0; k < s.nb; k++)
    for (int mot = 0; mot < NMOT; mot++)
      emot[mot] += dof_energy(m, phi, body_dof(&m->bodies[s.bodies[k]], mot));
  for (int mot = 0; mot < NMOT; mot++) esub += emot[mot];
  char motion[40] = "", phase[20] = "";
  int big[NMOT], dominant = 0;
  for (int mot = 0; mot < NMOT; mot++) {
    big[mot] = esub > 0 && emot[mot] >= SHARE_MOTION * esub;
    if (emot[mot] > emot[dominant]) dominant = mot;
  }
  const rr_body *one = s.nb == 1 ? &m->bodies[s.bodies[0]] : NULL;
  if (one && one->dof_y >= 0 && one->dof_phi >= 0 && big[MOT_Y] && big[MOT_PHI] && !big[MOT_PSI]) {
    snprintf(motion, sizeof motion, "%s", sway(one, phi));
  } else {
    for (int mot = 0; mot < NMOT; mot++)
      if (big[mot]) {
        size_t l = strlen(motion);
        snprintf(motion + l, sizeof motion - l, "%s%s", l ? "-" : "", motion_word[mot]);
      }
  }
  if (s.npair == 2) phase_suffix(m, s.pair, dominant, phi, phase, sizeof phase);
  snprintf(buf, len, "%s %s%s", s.word, motion, phase);
}

/* The shares into md; the groups' energies (not normalised) into eg, the
   total returned. */
static double energy_shares(const rr_model *m, const double complex *phi, rr_mode *md, double *eg)
{
  double tot = 0, roll = 0, froll = 0;
  for (int g = 0; g < RR_NGROUPS; g++) eg[g] = 0;
  for (int i = 0; i < m->n; i++) {
    double t = dof_energy(m, phi, i);
    eg[m->group[i]] += t;
    tot += t;
  }
  for (int b = 0; b < m->nbodies; b++) {
    double e = dof_energy(m, phi, m->bodies[b].dof_phi);
    roll += e;
    if (m->bodies[b].group == RR_GROUP_FRAME) froll += e;
  }
  for (int g = 0; g < RR_NGROUPS; g++) md->energy[g] = tot > 0 ? eg[g] / tot : 0;
  md->roll_share = tot > 0 ? roll / tot : 0;
  md->frame_roll_share = tot > 0 ? froll / tot : 0;
  return tot;
}

void rr_mode_energy(const rr_model *m, const double complex *phi, rr_mode *md)
{
  double eg[RR_NGROUPS];
  energy_shares(m, phi, md, eg);
}

void rr_mode_shares(const rr_model *m, const double complex *phi, rr_mode *md)
{
  double eg[RR_NGROUPS];
  if (energy_shares(m, phi, md, eg) > 0)
    name_mode(m, phi, eg, md->name, sizeof md->name);
  else
    snprintf(md->name, sizeof md->name, "none");
}
