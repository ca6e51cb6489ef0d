/* Gauss-Legendre nodes and weights on [-1, 1], computed by Newton's method in long double.
 * An m-point rule integrates polynomials of degree 2m-1 exactly. */
#ifndef AA_GAUSS_LEGENDRE_H
#define AA_GAUSS_LEGENDRE_H

#define AA_GL_MAX_POINTS 32

/* Fills node[0..m-1] (ascending) and weight[0..m-1]; 1 <= m <= AA_GL_MAX_POINTS. */
void aa_gauss_legendre(int m, double *node, double *weight);

#endif
