/* envlight_simd_part.h: the two halves of test_envlight_simd_scalar (envlight_simd_part.c) */
#ifndef ENVLIGHT_SIMD_PART_H
#define ENVLIGHT_SIMD_PART_H
#ifdef EL_NO_SIMD
#define ELS_PART(name) els_scalar_##name
#else
#define ELS_PART(name) els_simd_##name
#endif
#define ELS_FLOATS 28 /* the floats of one draw */
/* n draws of a light made from px (w x h RGB, light-to-world matrix m or NULL) and its hot spots (3%
 * weight): out[28 i ..] = sample_li's, sample_li_mix's and sample_li_mix_cos_table's (normal 0.2, 0.3,
 * 0.9) wi, rgb and pdf for u[2 i ..], then sample_li_cos_n's wi, pdf_li_cos_n's pdf at it and
 * sample_li_cos_n's pdf. Returns the light's hot spots, -1 when an init failed. */
int els_simd_draws(const float *px, int w, int h, const float m[9], const float *u, int n, float *out);
int els_scalar_draws(const float *px, int w, int h, const float m[9], const float *u, int n, float *out);
/* pdf_li_cos_le_n (issue 21) of a light made from px at n directions dirs[3 i ..] for normals nrm[3 i ..]:
 * out[4 i ..] = pdf, rgb. Returns 0, -1 when the init failed. */
int els_simd_pdf_le(const float *px, int w, int h, const float m[9], const float *nrm, const float *dirs, int n, float *out);
int els_scalar_pdf_le(const float *px, int w, int h, const float m[9], const float *nrm, const float *dirs, int n, float *out);
#endif
