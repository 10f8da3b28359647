!> Evaluation of load curves (*DEFINE_CURVE, scale factors and offsets already applied).
module mefem_curves
  use mefem_kinds, only: wp
  use mefem_model, only: curve_t
  implicit none
  private

  public :: curve_value

contains

  !> Value of a curve at abscissa t: linear interpolation between points and, as LS-DYNA
  !> does, linear extrapolation from the first/last two points outside the range (a curve
  !> of one point is constant).
  pure real(wp) function curve_value(curve, t)
    type(curve_t), intent(in) :: curve   !< the curve
    real(wp), intent(in) :: t            !< abscissa (usually time)
    integer :: lo, hi, mid, n
    n = curve%n
    if (n == 1) then
      curve_value = curve%f(1)
      return
    end if
    if (t <= curve%t(1)) then
      lo = 1
    else if (t >= curve%t(n)) then
      lo = n - 1
    else
      lo = 1
      hi = n
      do while (hi - lo > 1)
        mid = (lo + hi)/2
        if (curve%t(mid) <= t) then
          lo = mid
        else
          hi = mid
        end if
      end do
    end if
    curve_value = curve%f(lo) + (curve%f(lo+1) - curve%f(lo))*(t - curve%t(lo))/ &
                  (curve%t(lo+1) - curve%t(lo))
  end function curve_value

end module mefem_curves
