/* Eigenvalues of up to QRW matrices in SIMD lanes: a template, included by
 * hessenberg_qr.c once per lane count QRW (4: AVX2 or SSE2; 8: AVX-512), after the
 * single-matrix control it shares (qr_lane, lane_init, lane_advance).
 * Layout: entry (i, j) of lane c at b[((i ld + j) QRW + c], ld = n + 1;
 * row and column n are zero padding, so that a lane whose block ends early
 * (a 2-row reflector, r = 0) can share the 3-row arithmetic. Lanes share
 * each sweep's loop over the union of their blocks; outside its own range a
 * lane's reflector is the identity (x = y = z = q = r = 0), which leaves its
 * entries exactly as they were, and the entries it does touch beyond its
 * block are never read again for its eigenvalues. Per lane, the arithmetic
 * is the single-matrix algorithm's. */
#ifndef QR_CAT
#define QR_CAT_(a, b) a##b
#define QR_CAT(a, b) QR_CAT_(a, b)
#endif
#define vd QR_CAT(vd, QRW)
#define vl QR_CAT(vl, QRW)
#define sweep_lanes QR_CAT(sweep_lanes, QRW)
#define split_candidates QR_CAT(split_candidates, QRW)
#define reflector_lanes QR_CAT(reflector_lanes, QRW)
#define columns_lanes QR_CAT(columns_lanes, QRW)
#define near_lanes QR_CAT(near_lanes, QRW)
#define elmhes_lanes QR_CAT(elmhes_lanes, QRW)
#define sweep_start_lanes QR_CAT(sweep_start_lanes, QRW)
#define swap_lane QR_CAT(swap_lane, QRW)
#define swap_lanes QR_CAT(swap_lanes, QRW)
#define eig_lanes QR_CAT(eig_lanes, QRW)
/* The 8-lane bodies carry the AVX-512 target themselves: GCC lowers a
   function's vector operations for its own target before inlining it, so a
   default-target body would reach eig_batch8 with every lane compare split
   into scalar compares and inserts. */
#if QRW == 8
#define QR_TARGET __attribute__((target("arch=x86-64-v4")))
#else
#define QR_TARGET
#endif
typedef double vd __attribute__((vector_size(8 * QRW)));
typedef long long vl __attribute__((vector_size(8 * QRW)));

/* macros, not functions: a vector argument or result would change the ABI
   between the clones */
#define vsel(mask, a, b) ((vd)(((vl)(a) & (mask)) | ((vl)(b) & ~(mask))))
#define vabs(a) ((vd)((vl)(a) & ((vl){0} + INT64_MAX)))
#define vany(mask)                                                                                 \
  ({                                                                                               \
    vl m_ = (mask);                                                                                \
    long long o_ = 0;                                                                              \
    for (int c_ = 0; c_ < QRW; c_++) o_ |= m_[c_];                                                 \
    o_ != 0;                                                                                       \
  })

#define V(i, j) b[(size_t)(i) * (size_t)ld + (size_t)(j)]

/* Step k's reflectors, one per lane, into f[0..4] = (x, y, z, q, r); lanes
 * whose sweep does not cover k get the identity (zeros). A lane's first step
 * takes its (p0, q0, r0); the others read column k - 1 (rows k..k + 2: col,
 * as the previous step's near_lanes left them, or from memory where col is
 * NULL), whose subdiagonal entry V(k, k - 1) is set here. lm, ln: each lane's first and last step
 * (ld and -1 for an idle lane); neg: the lane's sweep starts below its l. */
QR_TARGET static inline __attribute__((always_inline)) void
reflector_lanes(vd *b, int ld, int k, const vl *lm, const vl *ln, const vl *neg, const vd *p0,
                const vd *q0, const vd *r0, const vd *col, vd *f)
{
  const vd zero = {0}, one = zero + 1;
  const vl kv = (vl){0} + k;
  vl on = (kv >= *lm) & (kv <= *ln), first = kv == *lm, last = kv == *ln, negate = first & *neg;
  vd p = *p0, q = *q0, r = *r0, x = one, pb0 = zero;
  if (k > 0) {
    vd pb = pb0 = col ? col[0] : V(k, k - 1), qb = col ? col[1] : V(k + 1, k - 1),
       rb = vsel(last, zero, col ? col[2] : V(k + 2, k - 1));
    vd xb = vabs(pb) + vabs(qb) + vabs(rb);
    vl scale = (xb != 0) & ((xb < 1e-100) | (xb > 1e100));
    if (vany(scale & ~first)) {
      vd ix = one / vsel(scale, xb, one);
      pb *= ix;
      qb *= ix;
      rb *= ix;
    }
    xb = vsel(scale, xb, one);
    p = vsel(first, *p0, pb);
    q = vsel(first, *q0, qb);
    r = vsel(first, *r0, rb);
    x = vsel(first, one, xb);
  }
  vd nrm = p * p + q * q + r * r;
  for (int c = 0; c < QRW; c++) nrm[c] = sqrt(nrm[c]);
  vd s = vsel(p >= 0, nrm, -nrm);
  on &= s != 0;
  if (k > 0) {
    V(k, k - 1) = vsel(on & first, vsel(negate, -pb0, pb0), vsel(on, -s * x, pb0));
    /* the bulge entries just read are not read again: cleared here rather
       than by the next sweep's start (lane_advance with clear = 0) */
    vl used = on & ~first;
    V(k + 1, k - 1) = vsel(used, zero, V(k + 1, k - 1));
    V(k + 2, k - 1) = vsel(used & ~last, zero, V(k + 2, k - 1));
  }
  s = vsel(on, s, one);
  vd is = one / s;
  p += s;
  vd ip = one / p;
  f[0] = vsel(on, p * is, zero);
  f[1] = vsel(on, q * is, zero);
  f[2] = vsel(on, r * is, zero);
  f[3] = vsel(on, q * ip, zero);
  f[4] = vsel(on, r * ip, zero);
}

/* Step k's reflectors f applied to the rows i0..i1 of columns k..k + 2. */
QR_TARGET static inline __attribute__((always_inline)) void
columns_lanes(vd *b, int ld, int k, int i0, int i1, const vd *f)
{
  vd x = f[0], y = f[1], z = f[2], q = f[3], r = f[4];
#pragma GCC unroll 4
  for (int i = i0; i <= i1; i++) {
    vd *ri = &V(i, k);
    vd a0 = ri[0], a1 = ri[1], a2 = ri[2], pp = x * a0 + y * a1 + z * a2;
    ri[2] = a2 - pp * r;
    ri[1] = a1 - pp * q;
    ri[0] = a0 - pp;
  }
}

/* The same for rows k + 1..k + 3 (those up to i1), their column-k entries
   also into col[0..2] for the next step's reflector (from memory where a row
   is past i1, when there is a next step), so that it need not read them
   back. */
QR_TARGET static inline __attribute__((always_inline)) void
near_lanes(vd *b, int ld, int k, int i1, int next, const vd *f, vd *col)
{
  vd x = f[0], y = f[1], z = f[2], q = f[3], r = f[4];
  for (int e = 0; e < 3; e++) {
    vd *ri = &V(k + 1 + e, k);
    if (k + 1 + e > i1) {
      col[e] = next ? ri[0] : (vd){0};
      continue;
    }
    vd a0 = ri[0], a1 = ri[1], a2 = ri[2], pp = x * a0 + y * a1 + z * a2;
    ri[2] = a2 - pp * r;
    ri[1] = a1 - pp * q;
    ri[0] = col[e] = a0 - pp;
  }
}

/* One sweep of every lane. Software-pipelined: after step k's row updates,
 * its column updates of rows k + 1..k + 3 (the ones step k + 1's reflector
 * reads) come first, then step k + 1's reflector, then step k's column
 * updates of the rows above, which nothing reads until later, so that the
 * reflector's sqrt and divisions run under them. Each entry still gets its
 * operations in the same order as step by step: bit-identical. */
QR_TARGET static inline __attribute__((always_inline)) void
sweep_lanes(vd *b, int ld, const qr_lane *lanes, const int *go)
{
  int kmin = ld, kmax = -1, lmin = ld, nmax = -1;
  vd p0, q0, r0;
  vl lm, ln, neg;
  for (int c = 0; c < QRW; c++) {
    const qr_lane *L = &lanes[c];
    lm[c] = go[c] ? L->m : ld;
    ln[c] = go[c] ? L->nn - 1 : -1;
    neg[c] = go[c] && L->l != L->m ? -1 : 0;
    if (!go[c]) {
      p0[c] = q0[c] = r0[c] = 0;
      continue;
    }
    kmin = MIN(kmin, L->m);
    kmax = MAX(kmax, L->nn - 1);
    lmin = MIN(lmin, L->l);
    nmax = MAX(nmax, L->nn);
    p0[c] = L->p;
    q0[c] = L->q;
    r0[c] = L->r;
  }
  if (kmax < kmin) return;
  vd f[5], g[5] = {{0}}, col[3];
  reflector_lanes(b, ld, kmin, &lm, &ln, &neg, &p0, &q0, &r0, NULL, f);
  for (int k = kmin; k <= kmax; k++) {
    vd x = f[0], y = f[1], z = f[2], q = f[3], r = f[4];
    vd *rk = &V(k, 0), *rk1 = &V(k + 1, 0), *rk2 = &V(k + 2, 0);
    /* each entry loaded once into a local: through the pointers, which the
       compiler must assume may alias, every store forced the others' reloads;
       unrolled, as the column updates are: these loops run ~20 times, and
       their overhead was ~3 % of a batch */
#pragma GCC unroll 4
    for (int j = k; j <= nmax; j++) {
      vd a0 = rk[j], a1 = rk1[j], a2 = rk2[j], pp = a0 + q * a1 + r * a2;
      rk2[j] = a2 - pp * z;
      rk1[j] = a1 - pp * y;
      rk[j] = a0 - pp * x;
    }
    int mmin = MIN(nmax, k + 3);
    near_lanes(b, ld, k, mmin, k < kmax, f, col);
    if (k < kmax) reflector_lanes(b, ld, k + 1, &lm, &ln, &neg, &p0, &q0, &r0, col, g);
    columns_lanes(b, ld, k, lmin, MIN(mmin, k), f);
    for (int e = 0; e < 5; e++) f[e] = g[e];
  }
}

/* split_row's first two tests for every lane at once, rows 1..nn of the
 * lanes still sweeping: the same arithmetic, so the same rows pass. Lane c
 * of *cand gets bit i for each row i that passes. */
QR_TARGET static inline __attribute__((always_inline)) void
split_candidates(const vd *b, int ld, const qr_lane *lanes, int nb, vl *cand)
{
  vl bits = {0};
  int top = 0;
  vd anorm = {0};
  for (int c = 0; c < QRW; c++) {
    anorm[c] = lanes[c].anorm;
    if (c < nb && lanes[c].status == 0) top = MAX(top, lanes[c].nn);
  }
  for (int i = 1; i <= top; i++) {
    vd h = vabs(V(i, i - 1)), s = vabs(V(i - 1, i - 1)) + vabs(V(i, i));
    s = vsel(s == 0, anorm, s);
    vl pass = (h <= DBL_MIN) | (h <= DBL_EPSILON * s);
    bits |= pass & ((vl){0} + (long long)(1ULL << i));
  }
  *cand = bits;
}

/* Rows and then columns m and pv interchanged in lane c alone. */
QR_TARGET static inline __attribute__((always_inline)) void swap_lane(double *s, int ld, int n,
                                                                      int m, int pv, int c)
{
  size_t L = QRW, P = (size_t)pv, M = (size_t)m, D = (size_t)ld, C = (size_t)c;
  for (size_t j = M - 1; j < (size_t)n; j++) {
    double t = s[(P * D + j) * L + C];
    s[(P * D + j) * L + C] = s[(M * D + j) * L + C];
    s[(M * D + j) * L + C] = t;
  }
  for (size_t i = 0; i < (size_t)n; i++) {
    double t = s[(i * D + P) * L + C];
    s[(i * D + P) * L + C] = s[(i * D + M) * L + C];
    s[(i * D + M) * L + C] = t;
  }
}

/* The same in the lanes of mask *mk at once. */
QR_TARGET static inline __attribute__((always_inline)) void swap_lanes(vd *b, int ld, int n, int m,
                                                                       int pv, const vl *mk)
{
  for (int j = m - 1; j < n; j++) {
    vd u = V(pv, j), w = V(m, j);
    V(pv, j) = vsel(*mk, w, u);
    V(m, j) = vsel(*mk, u, w);
  }
  for (int i = 0; i < n; i++) {
    vd u = V(i, pv), w = V(i, m);
    V(i, pv) = vsel(*mk, w, u);
    V(i, m) = vsel(*mk, u, w);
  }
}

/* Lanes that take one pivot row's interchange as a masked vector swap, not
 * lane by lane: a vector swap costs about what 2-3 scalar ones do (defined
 * once for both inclusions of this file). */
#ifndef SWAP_SHARED
#define SWAP_SHARED 3
#endif

/* sweep_start for every lane with go[c] at once, xyw[c] its shifts: row
 * by row from the highest lane's nn - 2 down, each lane from its own nn - 2
 * to where its own scan stops, with the single-matrix arithmetic, so that
 * every lane starts where it would alone, with the same first column. */
QR_TARGET static inline __attribute__((always_inline)) void
sweep_start_lanes(const vd *b, int ld, qr_lane *lanes, const int *go, const double (*xyw)[3])
{
  vd X, Y, W, P = {0}, Q = {0}, R = {0};
  vl lo, top, found, M = {0};
  int mtop = -1, mbot = ld;
  for (int c = 0; c < QRW; c++) {
    X[c] = go[c] ? xyw[c][0] : 0;
    Y[c] = go[c] ? xyw[c][1] : 0;
    W[c] = go[c] ? xyw[c][2] : 0;
    lo[c] = go[c] ? lanes[c].l : 0;
    top[c] = go[c] ? lanes[c].nn - 2 : -1;
    found[c] = go[c] ? 0 : -1;
    if (!go[c]) continue;
    mtop = MAX(mtop, lanes[c].nn - 2);
    mbot = MIN(mbot, lanes[c].l);
  }
  /* a row's test does not wait for the rows above: only the record of the
     first row that stops each lane runs from row to row */
  for (int m = mtop; m >= mbot; m--) {
    vl mv = (vl){0} + m;
    vd z = V(m, m), r = X - z, s = Y - z, h21 = V(m + 1, m);
    vd p = (r * s - W) + V(m, m + 1) * h21;
    vd q = (V(m + 1, m + 1) - z - r - s) * h21;
    r = V(m + 2, m + 1) * h21;
    vl stop = mv == lo;
    if (m > 0) {
      vd u = vabs(V(m, m - 1)) * (vabs(q) + vabs(r));
      vd v = vabs(p) * (vabs(V(m - 1, m - 1)) + vabs(z) + vabs(V(m + 1, m + 1)));
      stop |= u + v == v;
    }
    vl hit = ~found & (mv <= top) & stop;
    P = vsel(hit, p, P);
    Q = vsel(hit, q, Q);
    R = vsel(hit, r, R);
    M = (hit & mv) | (~hit & M);
    found |= hit;
    if (!vany(~found)) break;
  }
  for (int c = 0; c < QRW; c++) {
    if (!go[c]) continue;
    double sc = 1 / (fabs(P[c]) + fabs(Q[c]) + fabs(R[c]));
    lanes[c].m = (int)M[c];
    lanes[c].p = P[c] * sc;
    lanes[c].q = Q[c] * sc;
    lanes[c].r = R[c] * sc;
  }
}

/* elmhes in lanes: each lane pivots on its own; the lanes that share a
 * pivot row interchange together. */
QR_TARGET static inline __attribute__((always_inline)) void elmhes_lanes(int n, vd *b, int ld)
{
  vd y[64];
  double *s = (double *)b;
  for (int m = 1; m < n - 1; m++) {
    vd x = {0}, ax = {0};
    vl piv;
    for (int c = 0; c < QRW; c++) piv[c] = m;
    for (int j = m; j < n; j++) {
      vd v = V(j, m - 1), av = vabs(v);
      vl gt = av > ax;
      x = vsel(gt, v, x);
      ax = vsel(gt, av, ax);
      piv = (gt & ((vl){0} + j)) | (~gt & piv);
    }
    /* the interchanges: a pivot row that SWAP_SHARED or more lanes share as
       whole vectors under a mask, the others lane by lane */
    vl done = piv == ((vl){0} + m);
    for (int c = 0; c < QRW; c++) {
      if (done[c]) continue;
      vl mk = piv == ((vl){0} + piv[c]);
      done |= mk;
      int k = 0;
      for (int d = 0; d < QRW; d++) k += mk[d] != 0;
      for (int d = c; d < QRW && k < SWAP_SHARED; d++)
        if (mk[d]) swap_lane(s, ld, n, m, (int)piv[d], d);
      if (k >= SWAP_SHARED) swap_lanes(b, ld, n, m, (int)piv[c], &mk);
    }
    vl nz = x != 0;
    if (!vany(nz)) continue;
    vd rx = vsel(nz, x, (vd){0} + 1);
    const vd *rm = &V(m, 0);
    int any = 0;
    for (int i = m + 1; i < n; i++) {
      vd yi = V(i, m - 1) / rx;
      y[i] = yi;
      V(i, m - 1) = (vd){0};
      if (!vany(yi != 0)) continue;
      any = 1;
      vd *ri = &V(i, 0);
      for (int j = m; j < n; j++) ri[j] -= yi * rm[j];
    }
    if (!any) continue;
    for (int j = 0; j < n; j++) {
      vd d;
      DOT4(vd, &V(j, 0), y, m + 1, n, d);
      V(j, m) += d;
    }
  }
}
#undef V

QR_TARGET static inline __attribute__((always_inline)) int
eig_lanes(int n, int nb, const double *const *mats, double *wr, double *wi, double *work, int *fail)
{
  int ld = n + 1;
  /* vector-aligned start inside the caller's buffer */
  vd *b = (vd *)(((uintptr_t)work + sizeof(vd) - 1) & ~(uintptr_t)(sizeof(vd) - 1));
  double *s = (double *)b;
  /* idle lanes (never swept) copy lane 0, so that their pivots are lane
     0's and add no interchange of their own to elmhes */
  const double *src[QRW];
  for (int c = 0; c < QRW; c++) src[c] = mats[c < nb ? c : 0];
  for (int i = 0; i < n; i++) {
    for (int j = 0; j < n; j++) {
      vd e;
      for (int c = 0; c < QRW; c++) e[c] = src[c][i * n + j];
      b[(size_t)i * (size_t)ld + (size_t)j] = e;
    }
    b[(size_t)i * (size_t)ld + (size_t)n] = (vd){0};
  }
  for (int j = 0; j <= n; j++) b[(size_t)n * (size_t)ld + (size_t)j] = (vd){0};
  elmhes_lanes(n, b, ld);
  qr_lane lanes[QRW];
  int go[QRW];
  double wrs[QRW][64], wis[QRW][64];
  vd anorm = {0}; /* each lane's sum in rr_hqr's order */
  for (int i = 0; i < n; i++)
    for (int j = i > 0 ? i - 1 : 0; j < n; j++)
      anorm += vabs(b[(size_t)i * (size_t)ld + (size_t)j]);
  for (int c = 0; c < QRW; c++) lane_init(n, anorm[c], &lanes[c]);
  vl cand;
  double xyw[QRW][3];
  for (;;) {
    split_candidates(b, ld, lanes, nb, &cand);
    int any = 0;
    for (int c = 0; c < QRW; c++) {
      if (c < nb && lanes[c].status == 0)
        lane_advance(s + c, n, ld, QRW, &lanes[c], wrs[c], wis[c], 0, (unsigned long long)cand[c],
                     xyw[c]);
      go[c] = c < nb && lanes[c].status == 0;
      any |= go[c];
    }
    if (!any) break;
    sweep_start_lanes(b, ld, lanes, go, (const double(*)[3])xyw);
    sweep_lanes(b, ld, lanes, go);
  }
  int bad = 0;
  for (int c = 0; c < nb; c++) {
    fail[c] = lanes[c].status < 0;
    bad |= fail[c];
    memcpy(wr + (size_t)c * (size_t)n, wrs[c], sizeof(double) * (size_t)n);
    memcpy(wi + (size_t)c * (size_t)n, wis[c], sizeof(double) * (size_t)n);
  }
  return bad;
}
#undef vsel
#undef vabs
#undef vany
#undef vd
#undef vl
#undef sweep_lanes
#undef split_candidates
#undef reflector_lanes
#undef columns_lanes
#undef near_lanes
#undef elmhes_lanes
#undef sweep_start_lanes
#undef swap_lane
#undef swap_lanes
#undef eig_lanes
#undef QR_TARGET
