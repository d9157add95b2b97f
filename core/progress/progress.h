/***************************************************************************
  progress.h - what a long operation reports while it runs, and asks
  -------------------------------------------------------------------------
  One small type handed to every long operation of core - a bundle
  adjustment, a trace through a run, a road extraction, a map revision,
  an identification of control, a simulation: it reports the fraction
  done (0-1) and what it is doing, and asks, between steps short enough
  that a stop takes effect within a second, whether the caller wants it
  to stop. What stopping means for the result is the operation's own
  (its Summary says it was cancelled); the question is asked one way.

  A part of the work is a Progress of its own (part()): an operation that
  runs another reports the inner one's 0-1 into its share of its own.
  Once the caller has asked to stop, every part answers that it should.
 ***************************************************************************/
#ifndef GEOSTATION_PROGRESS_PROGRESS_H
#define GEOSTATION_PROGRESS_PROGRESS_H

#include <atomic>
#include <functional>
#include <memory>
#include <string>

namespace geostation
{

  class Progress
  {
    public:
      //! Told the fraction done of the whole operation (0-1) and a short message (may be empty).
      using Report = std::function<void( double fraction, const std::string &message )>;
      //! Asked whether to stop: true stops.
      using StopQuery = std::function<bool()>;

      //! Reports nowhere and never stops.
      Progress() = default;
      //! Either may be empty.
      Progress( Report report, StopQuery stop );

      /**
       * Reports `fraction` (0-1 of this part, clamped) and `message`;
       * returns false when the operation should stop (stopRequested()).
       */
      bool report( double fraction, const std::string &message = std::string() ) const;

      //! Whether the caller has asked to stop; once true, always true.
      bool stopRequested() const;

      /**
       * The span [from, to] (0 <= from <= to <= 1) of this progress as one
       * of its own: 0-1 reported into it lands in that span. Throws
       * std::invalid_argument for another span.
       */
      Progress part( double from, double to ) const;

    private:
      struct Hooks
      {
        Report report;
        StopQuery stop;
        mutable std::atomic<bool> stopped { false };
      };
      std::shared_ptr<const Hooks> mHooks;
      double mFrom = 0.0, mTo = 1.0;
  };

} // namespace geostation

#endif // GEOSTATION_PROGRESS_PROGRESS_H
