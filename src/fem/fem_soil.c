/* fem_soil.c - soil moduli and Gerber's penetration law (fem_soil.h). */
#include "fem_soil.h"

#include <math.h>

double fem_soil_oedometric_modulus(double E, double nu)
{
    return E * (1 - nu) / ((1 + nu) * (1 - 2 * nu));
}

double fem_soil_E_from_oedometric(double M_E, double nu)
{
    return M_E * (1 + nu) * (1 - 2 * nu) / (1 - nu);
}

double fem_soil_gerber_penetration(double mass, double M_E, double V)
{
    const double M_E_kN = M_E / 1e3; /* the law's unit: kN/m^2 */
    return 0.1 * cbrt(mass) * pow(M_E_kN, -0.4) * pow(V, 0.8);
}
