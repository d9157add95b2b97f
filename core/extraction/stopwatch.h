/***************************************************************************
  stopwatch.h - wall time of the extraction stages, for their summaries
 ***************************************************************************/
#ifndef GEOSTATION_EXTRACTION_STOPWATCH_H
#define GEOSTATION_EXTRACTION_STOPWATCH_H

#include <chrono>

namespace geostation
{

  //! Measures wall time from its construction (or the last restart()), in seconds.
  class Stopwatch
  {
    public:
      Stopwatch() : mStart( std::chrono::steady_clock::now() ) {}
      void restart() { mStart = std::chrono::steady_clock::now(); }
      double seconds() const { return std::chrono::duration<double>( std::chrono::steady_clock::now() - mStart ).count(); }

    private:
      std::chrono::steady_clock::time_point mStart;
  };

} // namespace geostation

#endif // GEOSTATION_EXTRACTION_STOPWATCH_H
