!> A minimal unit-test harness in plain Fortran (no framework is packaged in Debian).
!>
!> Each check prints one line, `PASS: name` or `FAIL: name: detail`; tests/run_tests.sh counts
!> these lines over all test programs. test_finish() prints the program's own tally and sets
!> the exit code (1 if anything failed), so a crash or an early exit is also seen as failure.
module mefem_testing
  use, intrinsic :: iso_fortran_env, only: output_unit
  use mefem_kinds, only: wp
  use mefem_comm, only: comm_init, comm_is_root
  use mefem_errors, only: terminate
  implicit none
  private

  public :: test_start, test_finish, check, check_close, check_equal, project_root

  integer :: n_pass = 0, n_fail = 0
  character(len=64) :: suite = ''

  !> Compare two values with tolerances.
  interface check_close
    module procedure check_close_scalar, check_close_array
  end interface check_close

contains

  !> Start a test program: MPI up, name recorded.
  subroutine test_start(name)
    character(len=*), intent(in) :: name   !< name of the test program
    call comm_init()
    suite = name
  end subroutine test_start

  !> Print this program's tally and exit (code 1 if any check failed).
  subroutine test_finish()
    character(len=32) :: a, b
    write(a, '(i0)') n_pass
    write(b, '(i0)') n_fail
    if (comm_is_root()) write(output_unit, '(a)') trim(suite)//': '//trim(a)//' passed, '// &
        trim(b)//' failed in this program'
    if (n_fail > 0) then
      call terminate(1)
    else
      call terminate(0)
    end if
  end subroutine test_finish

  !> Record a check that passes when cond is true.
  subroutine check(cond, name, detail)
    logical, intent(in) :: cond                     !< the assertion
    character(len=*), intent(in) :: name            !< what is checked
    character(len=*), intent(in), optional :: detail !< printed on failure
    if (cond) then
      n_pass = n_pass + 1
      if (comm_is_root()) write(output_unit, '(a)') 'PASS: '//trim(suite)//': '//trim(name)
    else
      n_fail = n_fail + 1
      if (comm_is_root()) then
        if (present(detail)) then
          write(output_unit, '(a)') 'FAIL: '//trim(suite)//': '//trim(name)//': '//trim(detail)
        else
          write(output_unit, '(a)') 'FAIL: '//trim(suite)//': '//trim(name)
        end if
      end if
    end if
    flush(output_unit)
  end subroutine check

  !> Pass when |got - want| <= atol + rtol*|want| (NaN always fails).
  subroutine check_close_scalar(got, want, rtol, name, atol)
    real(wp), intent(in) :: got, want           !< computed and expected values
    real(wp), intent(in) :: rtol                !< relative tolerance
    character(len=*), intent(in) :: name        !< what is checked
    real(wp), intent(in), optional :: atol      !< absolute tolerance (default 0)
    real(wp) :: a
    character(len=120) :: detail
    a = 0.0_wp
    if (present(atol)) a = atol
    write(detail, '(a,es24.16,a,es24.16)') 'got ', got, ' want ', want
    call check(abs(got - want) <= a + rtol*abs(want) .and. got == got, name, detail)
  end subroutine check_close_scalar

  !> Element-wise check_close_scalar; reports the worst entry.
  subroutine check_close_array(got, want, rtol, name, atol)
    real(wp), intent(in) :: got(:), want(:)     !< computed and expected values
    real(wp), intent(in) :: rtol                !< relative tolerance
    character(len=*), intent(in) :: name        !< what is checked
    real(wp), intent(in), optional :: atol      !< absolute tolerance (default 0)
    real(wp) :: a, excess, worst
    integer :: i, iworst
    character(len=160) :: detail
    logical :: ok
    a = 0.0_wp
    if (present(atol)) a = atol
    ok = size(got) == size(want)
    worst = -huge(1.0_wp)
    iworst = 1
    if (ok) then
      do i = 1, size(got)
        excess = abs(got(i) - want(i)) - (a + rtol*abs(want(i)))
        if (got(i) /= got(i)) excess = huge(1.0_wp)
        if (excess > worst) then
          worst = excess
          iworst = i
        end if
      end do
      ok = worst <= 0.0_wp
    end if
    if (size(got) == size(want) .and. size(got) > 0) then
      write(detail, '(a,i0,a,es24.16,a,es24.16)') 'entry ', iworst, ': got ', got(iworst), &
          ' want ', want(iworst)
    else
      write(detail, '(a,i0,a,i0)') 'sizes differ: ', size(got), ' vs ', size(want)
    end if
    call check(ok, name, detail)
  end subroutine check_close_array

  !> Pass when two integers are equal.
  subroutine check_equal(got, want, name)
    integer, intent(in) :: got, want            !< computed and expected values
    character(len=*), intent(in) :: name        !< what is checked
    character(len=80) :: detail
    write(detail, '(a,i0,a,i0)') 'got ', got, ' want ', want
    call check(got == want, name, detail)
  end subroutine check_equal

  !> Project root: $MEFEM_ROOT, else ../.. (the runner starts unit tests in tests/unit).
  function project_root() result(path)
    character(len=:), allocatable :: path
    character(len=1024) :: value
    integer :: length, status
    call get_environment_variable('MEFEM_ROOT', value, length, status)
    if (status == 0 .and. length > 0) then
      path = trim(value)
    else
      path = '../..'
    end if
  end function project_root

end module mefem_testing
