/***************************************************************************
  replaymain.cpp - runs fuzz targets over stored inputs, without libFuzzer
  -------------------------------------------------------------------------
    geostation_fuzz_replay [-v] <target> <file or folder>...

  Every file (folders: every file in them, sorted) goes through the named
  target once. The seed corpus and the regression inputs (inputs that once
  crashed a reader) run this way in the test suite, under the sanitizers
  too. Exit status 0 when every input ran; a finding aborts. -v prints what
  became of each input (read, or the reader's message).
 ***************************************************************************/
#include "fuzztarget.h"

#include <algorithm>
#include <cstdio>
#include <fstream>
#include <iterator>

int main( int argc, char **argv )
{
  if ( argc > 1 && std::string( argv[1] ) == "-v" )
  {
    geostation::fuzz::setVerbose( true );
    --argc;
    ++argv;
  }
  const geostation::fuzz::Entry entry = argc < 3 ? nullptr : geostation::fuzz::findTarget( argv[1] );
  if ( !entry )
  {
    std::fprintf( stderr, "usage: %s [-v] <target> <file or folder>...\ntargets:", argv[0] );
    for ( const std::string &name : geostation::fuzz::targetNames() )
      std::fprintf( stderr, " %s", name.c_str() );
    std::fprintf( stderr, "\n" );
    return 2;
  }
  std::vector<std::filesystem::path> files;
  for ( int i = 2; i < argc; ++i )
  {
    const std::filesystem::path path( argv[i] );
    if ( std::filesystem::is_directory( path ) )
    {
      for ( const auto &item : std::filesystem::directory_iterator( path ) )
        if ( item.is_regular_file() && item.path().filename().string().front() != '.' ) // .gitkeep
          files.push_back( item.path() );
    }
    else if ( std::filesystem::is_regular_file( path ) )
      files.push_back( path );
    else
    {
      std::fprintf( stderr, "%s: no such file or folder\n", argv[i] );
      return 2;
    }
  }
  std::sort( files.begin(), files.end() );
  for ( const auto &file : files )
  {
    std::ifstream in( file, std::ios::binary );
    const std::vector<char> bytes( ( std::istreambuf_iterator<char>( in ) ), std::istreambuf_iterator<char>() );
    std::fprintf( stderr, "%s\n", file.string().c_str() );
    entry( reinterpret_cast<const std::uint8_t *>( bytes.data() ), bytes.size() );
  }
  std::printf( "%s: %zu inputs ran\n", argv[1], files.size() );
  return files.empty() ? 1 : 0;
}
