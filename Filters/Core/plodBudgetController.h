// SPDX-License-Identifier: BSD-3-Clause
/**
 * @file plodBudgetController.h
 * @brief VTK-free frame-time target: steers the selector's triangle budget so that frames take
 * about a target time, smoothly (issue 14; the idea of vtkLODActor's allocated render time and
 * of Hoppe 1997's frame-rate regulation, with a control law of this project's).
 *
 * Each frame the caller reports what the frame cost (select + patch + render, seconds), the
 * triangles it drew and whether the budget bound the cut; the controller returns the budget
 * for the next frame. The law, in order:
 * 1. The measured time is the median of the last three frames: one slow frame (a page fault,
 *    another process) does not move the budget, and a real change moves it one frame later.
 * 2. Inside the dead band (|target / time - 1| <= DeadBand, default 5 %) nothing changes: at
 *    rest the budget stops moving, so a still view re-executes nothing.
 * 3. Otherwise the budget is scaled by `(target / time)^Gain` (default 0.5: half the
 *    correction a time proportional to the triangles would call for), at most MaxStep
 *    (default 1.25) up or down per frame. With a time `a + b N` the budget then approaches
 *    the target geometrically, from one side, without overshoot: no oscillation. The step
 *    limit also bounds what a frame can change on screen (no popping).
 * 4. The scaled quantity is the budget when it bound the cut, and the triangles actually drawn
 *    when it did not (the tolerances gave fewer: a distant or moving view). So the budget never
 *    runs away above what is drawn while the motion models or the tolerances keep the cut
 *    small, and when the view comes to rest detail returns at most MaxStep per frame.
 * 5. The result is clamped to [MinimumBudget, MaximumBudget].
 * A frame time that is not finite or not positive (a zero frame time) changes nothing.
 */
#ifndef plodBudgetController_h
#define plodBudgetController_h

#include <cstdint>
#include <string>

namespace plod
{

/// Settings of the frame-time target.
struct FrameTimeTarget
{
  double Target = 0;      ///< seconds per frame; 0 (or less): off
  double Gain = 0.5;      ///< exponent of target / time, in (0, 1]
  double MaxStep = 1.25;  ///< largest factor per frame (> 1)
  double DeadBand = 0.05; ///< relative error left alone, in [0, 0.5)
  int64_t MinimumBudget = 1000;
  int64_t MaximumBudget = INT64_MAX;
};

/// Checks the settings (finite, in range); explains in `why`.
bool ValidateFrameTimeTarget(const FrameTimeTarget& t, std::string* why);

class BudgetController
{
public:
  /**
   * The budget for the next frame, given the frame just measured: `seconds` (what it cost),
   * `drawn` (triangles drawn) and `binding` (the budget stopped refinement). Returns 0 when
   * the target is off or the settings are invalid (then the budget is not used).
   */
  int64_t Update(const FrameTimeTarget& settings, double seconds, int64_t drawn, bool binding);

  /// Forgets the history (a new model, a new target).
  void Reset();

  int64_t GetBudget() const { return this->Budget; }
  /// The median frame time the last update used (0 before the first).
  double GetMeasuredTime() const { return this->Measured; }

private:
  int64_t Budget = 0;
  double Recent[3] = { 0, 0, 0 };
  int Count = 0;
  double Measured = 0;
};

} // namespace plod

#endif
