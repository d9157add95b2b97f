/***************************************************************************
  libfuzzermain.cpp - libFuzzer's entry points for geostation_fuzz
  -------------------------------------------------------------------------
    GEOSTATION_FUZZ_TARGET=<target> geostation_fuzz [libFuzzer options] <corpus>...

  One program holds every target; the environment variable names the one
  that runs (scripts/fuzz.sh sets it and the corpus folders).
 ***************************************************************************/
#include "fuzztarget.h"

#include <cstdio>
#include <cstdlib>

namespace
{
  geostation::fuzz::Entry gEntry = nullptr;
}

extern "C" int LLVMFuzzerInitialize( int *, char *** )
{
  const char *name = std::getenv( "GEOSTATION_FUZZ_TARGET" );
  gEntry = name ? geostation::fuzz::findTarget( name ) : nullptr;
  if ( !gEntry )
  {
    std::fprintf( stderr, "set GEOSTATION_FUZZ_TARGET to one of:" );
    for ( const std::string &target : geostation::fuzz::targetNames() )
      std::fprintf( stderr, " %s", target.c_str() );
    std::fprintf( stderr, "\n" );
    std::exit( 2 );
  }
  return 0;
}

extern "C" int LLVMFuzzerTestOneInput( const std::uint8_t *data, std::size_t size )
{
  return gEntry( data, size );
}
