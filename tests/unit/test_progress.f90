!> Unit test of the progress reporter: duration text, progress line text, fraction done,
!> when lines are printed, peak memory.
! ranks: 1 2
program test_progress
  use mefem_kinds, only: wp
  use mefem_comm, only: comm_is_root
  use mefem_testing, only: test_start, test_finish, check, check_close
  use mefem_progress, only: progress_start, progress_update, progress_finish, progress_line, &
      progress_fraction, format_seconds, peak_memory_mib, PROGRESS_LINE_LENGTH
  implicit none

  character(len=PROGRESS_LINE_LENGTH) :: line
  logical :: printed(8)
  real(wp) :: memory
  integer :: k

  call test_start('progress')

  ! durations
  call check_text(format_seconds(0.0_wp), '0.0s')
  call check_text(format_seconds(3.24_wp), '3.2s')
  call check_text(format_seconds(9.97_wp), '10s')
  call check_text(format_seconds(45.0_wp), '45s')
  call check_text(format_seconds(125.0_wp), '2m05s')
  call check_text(format_seconds(3600.0_wp), '1h00m00s')
  call check_text(format_seconds(3723.4_wp), '1h02m03s')
  call check_text(format_seconds(90061.0_wp), '1d01h01m')
  call check_text(format_seconds(-1.0_wp), '--')
  call check_text(format_seconds(1.0e12_wp), '>99999d')

  ! fraction done: of end time, of end cycle, whichever is nearer its end
  call check_close(progress_fraction(10, 0.25_wp, 1.0_wp, 0), 0.25_wp, 1.0e-14_wp, &
                   'fraction of end time')
  call check_close(progress_fraction(50, 0.0_wp, 0.0_wp, 200), 0.25_wp, 1.0e-14_wp, &
                   'fraction of end cycle')
  call check_close(progress_fraction(80, 0.3_wp, 1.0_wp, 100), 0.8_wp, 1.0e-14_wp, &
                   'fraction: the end reached first counts')
  call check_close(progress_fraction(80, 1.5_wp, 1.0_wp, 0), 1.0_wp, 1.0e-14_wp, &
                   'fraction clipped to 1')
  call check(progress_fraction(80, 0.3_wp, 0.0_wp, 0) < 0.0_wp, 'no end: fraction unknown')

  ! the line text
  line = progress_line(1200, 1.2e-3_wp, 1.0e-6_wp, 0.12_wp, 3.2_wp, 23.4_wp)
  call check(index(line, 'cycle 1200') == 1, 'line starts with the cycle', trim(line))
  call check(index(line, 't  1.2000E-03') > 0, 'line has the time', trim(line))
  call check(index(line, 'dt  1.000E-06') > 0, 'line has dt', trim(line))
  call check(index(line, ' 12.0 %') > 0, 'line has the % done', trim(line))
  call check(index(line, 'wall 3.2s') > 0, 'line has the wall time', trim(line))
  call check(index(line, 'eta 23s') > 0, 'line has the ETA', trim(line))
  line = progress_line(7, 2.0_wp, 0.5_wp, 1.0_wp, 3723.0_wp, 0.0_wp, word='step')
  call check(index(line, 'step 7') == 1 .and. index(line, '100.0 %') > 0 .and. &
             index(line, 'wall 1h02m03s') > 0 .and. index(line, 'eta 0.0s') > 0, &
             'implicit line: step, 100 %, wall, eta', trim(line))
  line = progress_line(7, 2.0_wp, 0.5_wp, 0.5_wp, 10.0_wp, -1.0_wp)
  call check(index(line, ' 50.0 %') > 0 .and. index(line, 'eta --') > 0, &
             'unknown ETA printed as --', trim(line))
  line = progress_line(7, 2.0_wp, 0.5_wp, -1.0_wp, 10.0_wp, -1.0_wp)
  call check(index(line, '%') == 0 .and. index(line, 'eta') == 0, &
             'no end given: no % and no ETA', trim(line))

  ! when lines are printed: with a long interval only the first update and 10 % crossings
  call progress_start('test', 1.0_wp, 0, interval=1.0e6_wp)
  call progress_update(1, 0.001_wp, 1.0e-3_wp, printed(1))
  call progress_update(2, 0.05_wp, 1.0e-3_wp, printed(2))
  call progress_update(3, 0.10_wp, 1.0e-3_wp, printed(3))
  call progress_update(4, 0.15_wp, 1.0e-3_wp, printed(4))
  call progress_update(5, 0.45_wp, 1.0e-3_wp, printed(5))
  call progress_update(6, 0.47_wp, 1.0e-3_wp, printed(6))
  call progress_update(7, 1.00_wp, 1.0e-3_wp, printed(7))
  if (comm_is_root()) then
    call check(all(printed(1:7) .eqv. [.true., .false., .true., .false., .true., .false., &
               .true.]), 'prints first update and each 10 % crossing only')
  else
    call check(.not. any(printed(1:7)), 'other ranks print nothing')
  end if
  call progress_finish()

  ! with a zero interval every update prints
  call progress_start('test', 0.0_wp, 1000, interval=0.0_wp, word='step')
  do k = 1, 8
    call progress_update(k, 0.0_wp, 1.0_wp, printed(k))
  end do
  call check(all(printed .eqv. comm_is_root()), 'zero interval: every update prints on rank 0')
  call progress_finish()

  memory = peak_memory_mib()
  call check(memory > 0.0_wp .and. memory < 1.0e6_wp, 'peak memory is positive and plausible')

  call test_finish()

contains

  !> Check a fixed-length text against the expected text (trailing blanks ignored).
  subroutine check_text(got, want)
    character(len=*), intent(in) :: got    !< produced text
    character(len=*), intent(in) :: want   !< expected text
    call check(trim(got) == want, 'format_seconds gives '//want, 'got "'//trim(got)//'"')
  end subroutine check_text

end program test_progress
