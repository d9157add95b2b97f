/***************************************************************************
  fuzztarget.h - one entry point per fuzz target, for libFuzzer and replay
  -------------------------------------------------------------------------
  A target file defines its entry with GEOSTATION_FUZZ_TARGET( name ), which
  registers it by name. Two programs are built from the same target files:
  geostation_fuzz (libFuzzer, clang; the target named by the environment
  variable GEOSTATION_FUZZ_TARGET; scripts/fuzz.sh) and
  geostation_fuzz_replay (any compiler), which runs the seed corpus and the
  regression inputs as ordinary tests.

  A target accepts the documented failure of the reader it drives (the
  exception type its header names, with a message) and lets everything
  else escape: an undocumented exception, a crash or a sanitizer report is
  a finding.
 ***************************************************************************/
#ifndef GEOSTATION_TESTS_FUZZTARGET_H
#define GEOSTATION_TESTS_FUZZTARGET_H

#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <stdexcept>
#include <string>
#include <vector>

namespace geostation::fuzz
{
  using Entry = int ( * )( const std::uint8_t *data, std::size_t size );

  struct Registration
  {
    Registration( const char *name, Entry entry );
  };

  //! The registered target of that name, nullptr if there is none.
  Entry findTarget( const std::string &name );

  //! The names of the registered targets, sorted.
  std::vector<std::string> targetNames();

  //! A folder of this process's own below the system's temporary folder, made empty.
  std::filesystem::path scratchFolder( const std::string &name );

  //! Writes bytes to a file (throws std::runtime_error if it cannot).
  void writeBytes( const std::filesystem::path &file, const std::uint8_t *data, std::size_t size );

  /**
   * The input cut at lines that are exactly "%%" (the line ends on either
   * side of such a line belong to it): several files from one input, always `count` parts (missing
   * ones empty, extra ones appended to the last).
   */
  std::vector<std::string> splitParts( const std::uint8_t *data, std::size_t size, std::size_t count );

  //! Fails the run (abort) with a message: a property of the reader that does not hold.
  [[noreturn]] void violated( const std::string &what );

  //! A documented failure's message must say something (and is reported, see outcome()).
  void requireMessage( const std::exception &error );

  /**
   * What became of an input ("read: 3 images", or the documented failure's
   * message), printed by the replay program with -v, so the seed corpus can
   * be checked to reach past the first error. Silent otherwise.
   */
  void outcome( const std::string &what );

  //! Turns outcome() printing on (the replay program's -v).
  void setVerbose( bool verbose );
}

#define GEOSTATION_FUZZ_TARGET( name ) \
  static int fuzz_##name( const std::uint8_t *data, std::size_t size ); \
  static const geostation::fuzz::Registration registration_##name( #name, fuzz_##name ); \
  static int fuzz_##name( const std::uint8_t *data, std::size_t size )

#endif // GEOSTATION_TESTS_FUZZTARGET_H
