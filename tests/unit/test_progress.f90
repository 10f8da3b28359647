!> Unit test of the progress reporter: duration text, progress line text, fraction done,
!> when lines are printed, the histogram of cycle times and its percentiles, peak memory.
! ranks: 1 2
program test_progress
  use mefem_kinds, only: wp
  use mefem_comm, only: comm_is_root
  use mefem_testing, only: test_start, test_finish, check, check_close
  use mefem_progress, only: progress_start, progress_update, progress_finish, progress_line, &
      progress_fraction, format_seconds, peak_memory_mib, PROGRESS_LINE_LENGTH, &
      cycle_time_bin, cycle_time_percentile, CYCLE_BINS, CYCLE_BIN_RATIO, CYCLE_TIME_LOW
  implicit none

  character(len=PROGRESS_LINE_LENGTH) :: line
  logical :: printed(8)
  real(wp) :: memory, exact, got
  integer :: k, counts(CYCLE_BINS)

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

  ! cycle-time bins: edges, inside, below the first and beyond the last
  call check(cycle_time_bin(CYCLE_TIME_LOW*CYCLE_BIN_RATIO**9.5_wp) == 10, 'bin of a time in bin 10')
  call check(cycle_time_bin(CYCLE_TIME_LOW*CYCLE_BIN_RATIO**1000.2_wp) == 1001, &
             'bin of a time in bin 1001')
  call check(cycle_time_bin(0.5_wp*CYCLE_TIME_LOW) == 1 .and. cycle_time_bin(0.0_wp) == 1 .and. &
             cycle_time_bin(-1.0_wp) == 1, 'times below the first edge go to bin 1')
  call check(cycle_time_bin(1.0e12_wp) == CYCLE_BINS, 'times past the last edge go to the last bin')
  ! percentiles of the cycle times 1, 2, .., 100 ms: the k % percentile is k ms, given as the
  ! upper edge of its bin (at most one bin ratio above)
  counts = 0
  do k = 1, 100
    counts(cycle_time_bin(1.0e-3_wp*k)) = counts(cycle_time_bin(1.0e-3_wp*k)) + 1
  end do
  do k = 5, 95, 45
    exact = 1.0e-3_wp*k
    got = cycle_time_percentile(counts, real(k, wp))
    call check(got > exact .and. got <= exact*CYCLE_BIN_RATIO*(1.0_wp + 1.0e-12_wp), &
               'percentile of 1..100 ms within one bin', 'got '//rtext(got))
  end do
  call check(cycle_time_percentile(counts, 0.0_wp) > 1.0e-3_wp .and. &
             cycle_time_percentile(counts, 0.0_wp) <= 1.0e-3_wp*CYCLE_BIN_RATIO, &
             '0 % percentile is the shortest time')
  call check(cycle_time_percentile(counts, 100.0_wp) > 0.1_wp .and. &
             cycle_time_percentile(counts, 100.0_wp) <= 0.1_wp*CYCLE_BIN_RATIO, &
             '100 % percentile is the longest time')
  ! a slow tail of 10 cycles among 300 moves the mean, not the median
  counts = 0
  counts(cycle_time_bin(0.050_wp)) = 290
  counts(cycle_time_bin(0.080_wp)) = 10
  got = cycle_time_percentile(counts, 50.0_wp)
  call check(got > 0.050_wp .and. got <= 0.050_wp*CYCLE_BIN_RATIO, 'median ignores a slow tail')
  got = cycle_time_percentile(counts, 97.0_wp)
  call check(got > 0.080_wp .and. got <= 0.080_wp*CYCLE_BIN_RATIO, '97 % percentile is in the tail')
  counts = 0
  call check(cycle_time_percentile(counts, 50.0_wp) == 0.0_wp, 'empty histogram: percentile 0')

  memory = peak_memory_mib()
  call check(memory > 0.0_wp .and. memory < 1.0e6_wp, 'peak memory is positive and plausible')

  call test_finish()

contains

  !> A number as text for messages.
  function rtext(x) result(text)
    real(wp), intent(in) :: x          !< the number
    character(len=24) :: text
    write(text, '(es24.16)') x
  end function rtext

  !> Check a fixed-length text against the expected text (trailing blanks ignored).
  subroutine check_text(got, want)
    character(len=*), intent(in) :: got    !< produced text
    character(len=*), intent(in) :: want   !< expected text
    call check(trim(got) == want, 'format_seconds gives '//want, 'got "'//trim(got)//'"')
  end subroutine check_text

end program test_progress
