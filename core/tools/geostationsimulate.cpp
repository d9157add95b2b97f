/***************************************************************************
  geostationsimulate.cpp - geostation-simulate, the survey simulator's CLI
  -------------------------------------------------------------------------
  Takes the options of the Processing algorithm geostation:simulate_survey,
  as --output-dir DIR or OUTPUT_DIR=DIR alike.
 ***************************************************************************/
#include <algorithm>
#include <cctype>
#include <cstdio>
#include <iostream>
#include <map>
#include <string>

#include "simulation/surveysimulator.h"

namespace
{
  const char *kUsage =
    "usage: geostation-simulate --preset highway|aerial_stereo|oblique_photo --output-dir DIR [options]\n"
    "  (every option may also be written NAME=value, e.g. OUTPUT_DIR=out)\n"
    "  --seed N              random seed (default 1); the same seed gives the same output\n"
    "  --dem FILE            terrain from a GDAL DEM (any CRS, nodata allowed)\n"
    "  --roads FILE          roads from a line layer (reprojected to the block CRS)\n"
    "  --ortho FILE          orthophoto draped as ground texture\n"
    "  --stations N          stations (highway 30, aerial_stereo 3 images per strip)\n"
    "  --image-width N, --image-height N\n"
    "  --cameras N           highway: cameras on the van, 2..6 (default 3)\n"
    "  --spacing M           highway: metres between stations (default 5)\n"
    "  --gsd M               aerial_stereo: ground pixel size (default 0.10)\n"
    "  --scanned-film 1      oblique_photo: scanned film with fiducial marks\n"
    "  --noise SIGMA         Gaussian noise, grey levels (default 0)\n"
    "  --blur SIGMA          Gaussian blur, pixels\n"
    "  --vignetting F        fall-off at the corners, 0..1\n"
    "  --exposure GAIN       < 1 under-, > 1 over-exposed\n"
    "  --bit-errors RATE     salt-and-pepper fraction of pixels\n"
    "  --jpeg-quality Q      pass the images through JPEG at quality Q\n"
    "  --pose-noise-scale K  multiply the GNSS/INS sigmas (0: block = truth)\n"
    "  --supersampling N     N x N samples in edge pixels (default 3)\n"
    "  --threads N           worker threads (default: all cores)\n"
    "  --quiet               no progress output\n";

  std::string normalised( std::string name )
  {
    name.erase( 0, name.find_first_not_of( '-' ) );
    std::transform( name.begin(), name.end(), name.begin(), []( unsigned char c ) { return c == '-' ? '_' : static_cast<char>( std::toupper( c ) ); } );
    return name;
  }
}

int main( int argc, char **argv )
{
  std::map<std::string, std::string> values;
  bool quiet = false;
  for ( int i = 1; i < argc; ++i )
  {
    const std::string arg = argv[i];
    if ( arg == "-h" || arg == "--help" )
    {
      std::cout << kUsage;
      return 0;
    }
    if ( arg == "--quiet" || arg == "-q" )
    {
      quiet = true;
      continue;
    }
    const size_t eq = arg.find( '=' );
    if ( eq != std::string::npos )
      values[normalised( arg.substr( 0, eq ) )] = arg.substr( eq + 1 );
    else if ( arg.rfind( "--", 0 ) == 0 && i + 1 < argc )
      values[normalised( arg )] = argv[++i];
    else
    {
      std::cerr << "geostation-simulate: unexpected argument \"" << arg << "\"\n" << kUsage;
      return 2;
    }
  }

  geostation::SimulationOptions options;
  try
  {
    const auto take = [&]( const char *name ) -> const std::string *
    {
      const auto it = values.find( name );
      if ( it == values.end() )
        return nullptr;
      return &it->second;
    };
    const auto number = [&]( const char *name, double &target )
    {
      if ( const std::string *v = take( name ) )
      {
        size_t used = 0;
        target = std::stod( *v, &used );
        if ( used != v->size() )
          throw std::invalid_argument( std::string( name ) + " must be a number" );
      }
    };
    const auto integer = [&]( const char *name, auto &target )
    {
      double v = static_cast<double>( target );
      number( name, v );
      if ( v != static_cast<double>( static_cast<long long>( v ) ) )
        throw std::invalid_argument( std::string( name ) + " must be a whole number" );
      target = static_cast<std::remove_reference_t<decltype( target )>>( v );
    };
    options.preset = geostation::surveyPresetFromName( take( "PRESET" ) ? *take( "PRESET" ) : "highway" );
    if ( !take( "OUTPUT_DIR" ) )
      throw std::invalid_argument( "--output-dir is required" );
    options.outputDir = *take( "OUTPUT_DIR" );
    if ( take( "DEM" ) )
      options.demPath = *take( "DEM" );
    if ( take( "ROADS" ) )
      options.roadsPath = *take( "ROADS" );
    if ( take( "ORTHO" ) )
      options.orthoPath = *take( "ORTHO" );
    integer( "SEED", options.seed );
    integer( "STATIONS", options.stations );
    integer( "IMAGE_WIDTH", options.imageWidth );
    integer( "IMAGE_HEIGHT", options.imageHeight );
    integer( "CAMERAS", options.cameras );
    number( "SPACING", options.stationSpacingM );
    number( "GSD", options.groundPixelSizeM );
    number( "NOISE", options.degradation.noiseSigma );
    number( "BLUR", options.degradation.blurSigmaPx );
    number( "VIGNETTING", options.degradation.vignetting );
    number( "EXPOSURE", options.degradation.exposure );
    number( "BIT_ERRORS", options.degradation.bitErrorRate );
    integer( "JPEG_QUALITY", options.degradation.jpegQuality );
    number( "POSE_NOISE_SCALE", options.poseNoiseScale );
    integer( "SUPERSAMPLING", options.supersampling );
    int film = 0;
    integer( "SCANNED_FILM", film );
    options.scannedFilm = film != 0;
    integer( "THREADS", options.threads );
    for ( const auto &[name, value] : values )
    {
      static const char *known[] = { "PRESET", "OUTPUT_DIR", "DEM", "ROADS", "ORTHO", "SEED", "STATIONS", "IMAGE_WIDTH", "IMAGE_HEIGHT", "CAMERAS", "SPACING", "GSD",
                                     "NOISE", "BLUR", "VIGNETTING", "EXPOSURE", "BIT_ERRORS", "JPEG_QUALITY", "POSE_NOISE_SCALE", "SUPERSAMPLING", "THREADS",
                                     "SCANNED_FILM" };
      if ( std::find_if( std::begin( known ), std::end( known ), [&]( const char *k ) { return name == k; } ) == std::end( known ) )
        throw std::invalid_argument( "unknown option " + name );
      (void)value;
    }
  }
  catch ( const std::exception &e )
  {
    std::cerr << "geostation-simulate: " << e.what() << "\n";
    return 2;
  }

  if ( !quiet )
    options.progress = geostation::Progress( []( double fraction, const std::string &message )
    {
      std::fprintf( stderr, "\r%3d%%  %-40s", static_cast<int>( fraction * 100 + 0.5 ), message.c_str() );
    }, nullptr );
  try
  {
    const geostation::SimulationSummary summary = geostation::simulateSurvey( options );
    if ( !quiet )
      std::fprintf( stderr, "\n" );
    std::printf( "%d images (%d stations) in %s, CRS %s\n", summary.images, summary.stations, options.outputDir.string().c_str(), summary.crs.size() < 40 ? summary.crs.c_str() : "from the DEM" );
    std::printf( "rendered %.1f Mpx in %.2f s (%.2f Mpx/s, %.2f rays per pixel)\n", summary.pixels / 1e6, summary.renderSeconds,
                 summary.pixels / 1e6 / std::max( 1e-9, summary.renderSeconds ), static_cast<double>( summary.rays ) / std::max( 1L, summary.pixels ) );
    std::printf( "truth: %d objects, %d control points, %d road lines, %ld image observations\n", summary.objects, summary.controlPoints, summary.roadLines,
                 summary.imageTruthRows );
    for ( const std::string &note : summary.notes )
      std::printf( "note: %s\n", note.c_str() );
    return 0;
  }
  catch ( const std::invalid_argument &e )
  {
    std::fprintf( stderr, "\ngeostation-simulate: %s\n", e.what() );
    return 2;
  }
  catch ( const std::exception &e )
  {
    std::fprintf( stderr, "\ngeostation-simulate: %s\n", e.what() );
    return 1;
  }
}
