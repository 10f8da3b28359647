!> Parsing of numbers as LS-DYNA decks write them.
!>
!> Reals: `1`, `-1.5`, `.5`, `2.`, `1.0E+05`, `1e5`, `1.0D-3`, and the Fortran compact exponent
!> without a letter: `8.9-3` = 8.9e-3, `1.0+5` = 1.0e5. Integers: optional sign and digits; a real
!> with an integral value (`3.`, `3.0`, `1e3`) is accepted where an integer is expected, because
!> decks written by pre-processors do that. No internal blanks. The common case is converted
!> exactly by integer arithmetic (mantissa below 2**53, power of ten below 1e23: one correctly
!> rounded multiply or divide); anything else goes through Fortran's own conversion.
module mefem_numbers
  use mefem_kinds, only: wp, i8
  implicit none
  private

  public :: parse_real, parse_int

  !> Decimal exponent of huge(1.0_wp) (1.8e308)
  integer, parameter :: MAX_DECIMAL_EXPONENT = int(log10(huge(1.0_wp)))

  !> Powers of ten that are exact in double precision.
  real(wp), parameter :: EXACT_POWERS(0:22) = [ &
    1.0e0_wp, 1.0e1_wp, 1.0e2_wp, 1.0e3_wp, 1.0e4_wp, 1.0e5_wp, 1.0e6_wp, 1.0e7_wp, 1.0e8_wp, &
    1.0e9_wp, 1.0e10_wp, 1.0e11_wp, 1.0e12_wp, 1.0e13_wp, 1.0e14_wp, 1.0e15_wp, 1.0e16_wp, &
    1.0e17_wp, 1.0e18_wp, 1.0e19_wp, 1.0e20_wp, 1.0e21_wp, 1.0e22_wp]

contains

  !> Read a real number from text s (already trimmed of blanks). ok is false if s is no number.
  pure subroutine parse_real(s, x, ok, overflow)
    character(len=*), intent(in) :: s   !< the field text, no leading/trailing blanks
    real(wp), intent(out) :: x          !< the value
    logical, intent(out) :: ok          !< true when s is a valid number
    logical, intent(out), optional :: overflow  !< s is a number beyond huge(x) (ok false)
    integer :: i, n, exp_sign, n_digits, ios
    integer(i8) :: mantissa
    integer :: exp10, exp_value, dropped
    logical :: negative, seen_dot, seen_digit
    character(len=64) :: normal
    character :: c

    x = 0.0_wp
    ok = .false.
    if (present(overflow)) overflow = .false.
    n = len(s)
    if (n == 0) return
    i = 1
    negative = .false.
    if (s(1:1) == '-' .or. s(1:1) == '+') then
      negative = s(1:1) == '-'
      i = 2
    end if
    mantissa = 0_i8
    exp10 = 0
    n_digits = 0
    dropped = 0
    seen_dot = .false.
    seen_digit = .false.
    do while (i <= n)
      c = s(i:i)
      if (c >= '0' .and. c <= '9') then
        seen_digit = .true.
        if (n_digits < 18) then
          if (mantissa > 0 .or. c /= '0') n_digits = n_digits + 1
          mantissa = mantissa*10_i8 + int(iachar(c) - iachar('0'), i8)
          if (seen_dot) exp10 = exp10 - 1
        else
          dropped = dropped + 1
          if (.not. seen_dot) exp10 = exp10 + 1
        end if
      else if (c == '.' .and. .not. seen_dot) then
        seen_dot = .true.
      else
        exit
      end if
      i = i + 1
    end do
    if (.not. seen_digit) return
    ! exponent: E/D letter with optional sign, or a bare sign (Fortran compact form)
    exp_value = 0
    if (i <= n) then
      c = s(i:i)
      if (index('EeDd', c) > 0) then
        i = i + 1
        if (i > n) return
        c = s(i:i)
      end if
      exp_sign = 1
      if (c == '+' .or. c == '-') then
        if (c == '-') exp_sign = -1
        i = i + 1
      else if (index('EeDd', s(i-1:i-1)) == 0) then
        return                         ! neither a letter nor a sign: not a number
      end if
      if (i > n) return
      do while (i <= n)
        c = s(i:i)
        if (c < '0' .or. c > '9') return
        if (exp_value < 100000) exp_value = exp_value*10 + (iachar(c) - iachar('0'))
        i = i + 1
      end do
      exp_value = exp_sign*exp_value
    end if
    exp10 = exp10 + exp_value
    if (mantissa == 0_i8) then
      ok = .true.
      x = 0.0_wp
      if (negative) x = -x
      return
    end if
    if (mantissa < 2_i8**53 .and. abs(exp10) <= 22) then
      if (exp10 >= 0) then
        x = real(mantissa, wp)*EXACT_POWERS(exp10)
      else
        x = real(mantissa, wp)/EXACT_POWERS(-exp10)
      end if
    else
      ! beyond double precision: decided before converting (a conversion that overflows
      ! traps in the debug build); the value is mantissa 10^exp10, of n_digits digits
      if (exp10 + n_digits - 1 > MAX_DECIMAL_EXPONENT) then
        if (present(overflow)) overflow = .true.
        return
      end if
      if (exp10 < -400) then
        x = 0.0_wp
      else if (exp10 + n_digits - 1 == MAX_DECIMAL_EXPONENT) then
        ! 1e308 <= |x| < 1e309: compare a scaled conversion with huge
        write(normal, '(i0,a,i0)') mantissa, 'e', exp10 - 10
        read(normal, *, iostat=ios) x
        if (ios /= 0) return
        if (x > huge(x)/1.0e10_wp) then
          if (present(overflow)) overflow = .true.
          return
        end if
        x = x*1.0e10_wp
      else
        write(normal, '(i0,a,i0)') mantissa, 'e', exp10
        read(normal, *, iostat=ios) x
        if (ios /= 0) return
      end if
    end if
    if (negative) x = -x
    ok = .true.
  end subroutine parse_real

  !> Read an integer from text s (trimmed). Integral reals such as `3.` are accepted.
  pure subroutine parse_int(s, k, ok)
    character(len=*), intent(in) :: s   !< the field text, no leading/trailing blanks
    integer, intent(out) :: k           !< the value
    logical, intent(out) :: ok          !< true when s is a valid integer in range
    integer :: i, n, start
    integer(i8) :: v
    real(wp) :: x
    k = 0
    ok = .false.
    n = len(s)
    if (n == 0) return
    start = 1
    if (s(1:1) == '-' .or. s(1:1) == '+') start = 2
    if (start > n) return
    v = 0_i8
    do i = start, n
      if (s(i:i) < '0' .or. s(i:i) > '9') exit
      if (v > 10_i8**12) return        ! far beyond the integer range
      v = v*10_i8 + int(iachar(s(i:i)) - iachar('0'), i8)
    end do
    if (i > n) then
      if (s(1:1) == '-') v = -v
      if (abs(v) > int(huge(k), i8)) return
      k = int(v)
      ok = .true.
      return
    end if
    call parse_real(s, x, ok)
    if (.not. ok) return
    ok = .false.
    if (x /= aint(x) .or. abs(x) > real(huge(k), wp)) return
    k = int(x)
    ok = .true.
  end subroutine parse_int

end module mefem_numbers
