/***************************************************************************
  proceduralnoise.h - seeded value noise for terrain and ground textures
  -------------------------------------------------------------------------
  Deterministic for a seed on every platform (integer hashing, no global
  random state). The band-limited fBm drops octaves finer than the pixel
  footprint, so the rendered texture does not alias: area matching sees a
  texture like a real camera would, sharp where the image resolves it.
 ***************************************************************************/
#ifndef GEOSTATION_SIMULATION_PROCEDURALNOISE_H
#define GEOSTATION_SIMULATION_PROCEDURALNOISE_H

#include <cmath>
#include <cstdint>

namespace geostation::noise
{

  inline uint32_t hash( int32_t x, int32_t y, uint32_t seed )
  {
    uint32_t h = seed * 0x9E3779B1u;
    h ^= static_cast<uint32_t>( x ) * 0x85EBCA6Bu;
    h = ( h << 13 ) | ( h >> 19 );
    h ^= static_cast<uint32_t>( y ) * 0xC2B2AE35u;
    h ^= h >> 16;
    h *= 0x7FEB352Du;
    h ^= h >> 15;
    h *= 0x846CA68Bu;
    h ^= h >> 16;
    return h;
  }

  //! Uniform in [-1, 1) for an integer lattice point.
  inline double lattice( int32_t x, int32_t y, uint32_t seed )
  {
    return hash( x, y, seed ) * ( 2.0 / 4294967296.0 ) - 1.0;
  }

  //! Smooth value noise in [-1, 1] with unit lattice spacing (quintic fade).
  inline double value( double x, double y, uint32_t seed )
  {
    const double fx = std::floor( x ), fy = std::floor( y );
    const int32_t ix = static_cast<int32_t>( fx ), iy = static_cast<int32_t>( fy );
    const double u = x - fx, v = y - fy;
    const double su = u * u * u * ( u * ( u * 6 - 15 ) + 10 ), sv = v * v * v * ( v * ( v * 6 - 15 ) + 10 );
    const double a = lattice( ix, iy, seed ), b = lattice( ix + 1, iy, seed );
    const double c = lattice( ix, iy + 1, seed ), d = lattice( ix + 1, iy + 1, seed );
    return ( a + ( b - a ) * su ) + ( ( c + ( d - c ) * su ) - ( a + ( b - a ) * su ) ) * sv;
  }

  /**
   * Fractal noise of `octaves` octaves from `wavelengthM` down by halves,
   * amplitude `gain`^i, roughly in [-1, 1]. Octaves whose wavelength is below
   * two footprints (the Nyquist limit) are left out, fading in up to three.
   */
  inline double fbm( double x, double y, double wavelengthM, int octaves, double footprintM, uint32_t seed, double gain = 0.55 )
  {
    double sum = 0.0, norm = 0.0, amplitude = 1.0, wavelength = wavelengthM;
    for ( int i = 0; i < octaves; ++i )
    {
      const double ratio = wavelength / footprintM;
      const double weight = ratio >= 3.0 ? 1.0 : ( ratio <= 2.0 ? 0.0 : ratio - 2.0 );
      if ( weight > 0.0 )
        sum += weight * amplitude * value( x / wavelength, y / wavelength, seed + 7919u * static_cast<uint32_t>( i ) );
      norm += amplitude;
      amplitude *= gain;
      wavelength *= 0.5;
      if ( weight == 0.0 )
        break;
    }
    return norm > 0.0 ? sum / norm * 1.6 : 0.0;
  }

} // namespace geostation::noise

#endif // GEOSTATION_SIMULATION_PROCEDURALNOISE_H
