/* fem_soil.h - soil moduli as practitioners give them, in the FE model's
 * parameters, and the empirical penetration law the soil model is compared
 * with (docs/soil-impacts.md).  Internal to src/fem, the tests and the
 * benchmarks.  SI units: moduli in Pa, masses in kg, speeds in m/s, depths
 * in m. */
#ifndef ROCKFUZZ_FEM_SOIL_H
#define ROCKFUZZ_FEM_SOIL_H

/* Oedometric (constrained) modulus of an isotropic elastic solid:
 * E_oed = E (1 - nu) / ((1 + nu)(1 - 2 nu)), nu in [0, 0.5). */
double fem_soil_oedometric_modulus(double E, double nu);

/* Its inverse: the Young's modulus E whose oedometric modulus is M_E,
 * E = M_E (1 + nu)(1 - 2 nu) / (1 - nu).  How a compressibility modulus M_E
 * (plate-load or oedometer, Gerber's M_E) becomes the model's E. */
double fem_soil_E_from_oedometric(double M_E, double nu);

/* Gerber's empirical penetration of a block into soil (as cited in Lu et
 * al. 2019): d = 0.1 M^(1/3) M_E^(-0.4) V^0.8 with d [m], M [kg], M_E in
 * kN/m^2 and V [m/s] the normal impact speed.  Here M_E is taken in Pa and
 * converted (kN/m^2 = 1e3 Pa); returns d [m]. */
double fem_soil_gerber_penetration(double mass, double M_E, double V);

#endif
