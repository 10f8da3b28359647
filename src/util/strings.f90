!> Small string helpers used across mefem.
module mefem_strings
  use mefem_kinds, only: wp
  implicit none
  private

  public :: to_upper, to_lower, itoa, rtoa, starts_with, dirname, join_path, is_absolute_path

contains

  !> Upper-case copy of an ASCII string.
  pure function to_upper(s) result(u)
    character(len=*), intent(in) :: s   !< input text
    character(len=len(s)) :: u
    integer :: i, c
    u = s
    do i = 1, len(s)
      c = iachar(s(i:i))
      if (c >= iachar('a') .and. c <= iachar('z')) u(i:i) = achar(c - 32)
    end do
  end function to_upper

  !> Lower-case copy of an ASCII string.
  pure function to_lower(s) result(u)
    character(len=*), intent(in) :: s   !< input text
    character(len=len(s)) :: u
    integer :: i, c
    u = s
    do i = 1, len(s)
      c = iachar(s(i:i))
      if (c >= iachar('A') .and. c <= iachar('Z')) u(i:i) = achar(c + 32)
    end do
  end function to_lower

  !> Integer as text without blanks.
  pure function itoa(i) result(s)
    integer, intent(in) :: i   !< the integer
    character(len=:), allocatable :: s
    character(len=24) :: buf
    write(buf, '(i0)') i
    s = trim(buf)
  end function itoa

  !> Real as short text with 6 significant digits: plain notation between 1e-3 and 1e6
  !> ("0.00628", "210000"), scientific outside ("1.5e-09"); no trailing zeros.
  pure function rtoa(x) result(s)
    real(wp), intent(in) :: x   !< the number
    character(len=:), allocatable :: s
    character(len=32) :: buf
    integer :: e, k, decimals
    if (x == 0.0_wp) then
      s = '0'
      return
    end if
    e = floor(log10(abs(x)))
    if (e >= -3 .and. e < 6) then
      decimals = max(0, 5 - e)
      write(buf, '(f0.'//achar(iachar('0') + decimals)//')') x
      s = trim(adjustl(buf))
      if (index(s, '.') > 0) then
        k = len(s)
        do while (s(k:k) == '0')
          k = k - 1
        end do
        if (s(k:k) == '.') k = k - 1
        s = s(1:k)
      end if
      if (s(1:1) == '.') s = '0'//s
      if (len(s) > 1) then
        if (s(1:2) == '-.') s = '-0'//s(2:)
      end if
    else
      write(buf, '(es14.5e3)') x
      s = trim(adjustl(buf))
      k = index(s, 'E')
      buf = s(k+1:)
      s = s(1:k-1)
      do while (s(len(s):len(s)) == '0')
        s = s(1:len(s)-1)
      end do
      if (s(len(s):len(s)) == '.') s = s(1:len(s)-1)
      ! exponent without leading zeros beyond two digits: e+006 -> e+06
      if (buf(2:2) == '0') buf = buf(1:1)//buf(3:)
      s = s//'e'//trim(buf)
    end if
  end function rtoa

  !> True when s begins with prefix.
  pure logical function starts_with(s, prefix)
    character(len=*), intent(in) :: s, prefix   !< text and the prefix looked for
    starts_with = .false.
    if (len(prefix) > len(s)) return
    starts_with = s(1:len(prefix)) == prefix
  end function starts_with

  !> Directory part of a path ('' for a bare file name), without the trailing '/'.
  pure function dirname(path) result(d)
    character(len=*), intent(in) :: path   !< a file path
    character(len=:), allocatable :: d
    integer :: k
    k = index(path, '/', back=.true.)
    if (k == 0) then
      d = ''
    else if (k == 1) then
      d = '/'
    else
      d = path(1:k-1)
    end if
  end function dirname

  !> True for a path that starts at the file system root.
  pure logical function is_absolute_path(path)
    character(len=*), intent(in) :: path   !< a file path
    is_absolute_path = .false.
    if (len(path) > 0) is_absolute_path = path(1:1) == '/'
  end function is_absolute_path

  !> dir/name, or name alone when dir is empty or name is absolute.
  pure function join_path(dir, name) result(p)
    character(len=*), intent(in) :: dir, name   !< directory and file name
    character(len=:), allocatable :: p
    if (len(dir) == 0 .or. is_absolute_path(name)) then
      p = name
    else if (dir(len(dir):len(dir)) == '/') then
      p = dir//name
    else
      p = dir//'/'//name
    end if
  end function join_path

end module mefem_strings
