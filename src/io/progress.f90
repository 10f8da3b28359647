!> Progress reporter of a time loop: a short line now and then, and a summary at the end.
!>
!> progress_update may be called every cycle of an explicit run: when it does not print it
!> costs one wall-clock read and a few comparisons (O(1), no allocation, no communication),
!> and on ranks other than 0 it returns at once. It prints (rank 0, via `say`) on the first
!> call, whenever `interval` seconds of wall time have passed since the last line (default 5 s)
!> and whenever the fraction done crosses a multiple of 10 %. The fraction done is that of
!> end_time or of end_cycle, whichever is nearer to its end. The estimated time to completion
!> uses the rate of progress since the first update (so set-up time and, after a restart, the
!> part already done do not distort it).
!>
!> progress_start and progress_finish must be called on every rank (progress_finish reduces
!> the peak memory over ranks).
!>
!> Rank 0 also keeps the distribution of the wall time between successive updates (the wall
!> time of each cycle, or step) in a histogram of logarithmic bins, each CYCLE_BIN_RATIO wide,
!> and the summary gives its 5, 50 and 95 % percentiles. The median cycle is what a run
!> costs without the few slow cycles (output, a busy host): on a shared machine it is a
!> steadier figure than the mean (doc/performance.md).
module mefem_progress
  use, intrinsic :: iso_fortran_env, only: int64
  use mefem_kinds, only: wp
  use mefem_comm, only: comm_is_root, comm_wtime, comm_max
  use mefem_errors, only: say
  implicit none
  private

  public :: progress_start, progress_update, progress_finish
  public :: progress_line, progress_fraction, format_seconds, peak_memory_mib
  public :: cycle_time_bin, cycle_time_percentile

  integer, parameter, public :: PROGRESS_LINE_LENGTH = 160  !< length of progress_line's text
  integer, parameter, public :: SECONDS_TEXT_LENGTH = 16    !< length of format_seconds' text
  real(wp), parameter :: DEFAULT_INTERVAL = 5.0_wp          !< seconds between two lines
  !> Fraction of a tenth below which the fraction done counts as having reached that tenth
  real(wp), parameter :: DECILE_TOLERANCE = 1.0e-9_wp
  ! histogram of cycle wall times: bin k (1..CYCLE_BINS) holds [t_k, t_k*ratio) with
  ! t_k = CYCLE_TIME_LOW*ratio**(k-1); shorter times go to bin 1, longer ones to the last
  real(wp), parameter, public :: CYCLE_TIME_LOW = 1.0e-7_wp  !< lower edge of bin 1 (s)
  real(wp), parameter, public :: CYCLE_BIN_RATIO = 1.005_wp  !< upper/lower edge of a bin
  integer, parameter, public :: CYCLE_BINS = 6000            !< bins: up to about 1e6 s

  character(len=64) :: run_label = ''        !< prefix of every line, e.g. "explicit"
  character(len=16) :: step_word = 'cycle'   !< "cycle" (explicit) or "step" (implicit)
  real(wp) :: run_end_time = 0.0_wp          !< end time (<= 0: none)
  integer :: run_end_cycle = 0               !< last cycle (<= 0: none)
  real(wp) :: print_interval = DEFAULT_INTERVAL
  real(wp) :: wall_start = 0.0_wp            !< comm_wtime() at progress_start
  real(wp) :: wall_first = 0.0_wp            !< wall time (from start) of the first update
  real(wp) :: wall_last_print = 0.0_wp       !< wall time (from start) of the last line
  real(wp) :: fraction_first = 0.0_wp        !< fraction done at the first update
  integer :: last_decile = -1                !< tens of percent reported so far
  logical :: active = .false.                !< between progress_start and progress_finish
  logical :: updated = .false.               !< progress_update called since progress_start
  integer :: first_cycle = 0, last_cycle = 0 !< cycles of the first and latest updates
  real(wp) :: last_time = 0.0_wp             !< simulation time of the latest update
  real(wp) :: wall_previous = 0.0_wp         !< wall time (from start) of the latest update
  integer :: cycle_counts(CYCLE_BINS) = 0    !< histogram of the wall times between updates

contains

  !> Begin reporting a run (call on every rank).
  subroutine progress_start(label, end_time, end_cycle, interval, word)
    character(len=*), intent(in) :: label             !< prefix of the lines, e.g. "explicit"
    real(wp), intent(in) :: end_time                  !< end time of the run (<= 0: none)
    integer, intent(in) :: end_cycle                  !< last cycle of the run (<= 0: none)
    real(wp), intent(in), optional :: interval        !< seconds between lines (default 5)
    character(len=*), intent(in), optional :: word    !< "cycle" (default) or "step"
    run_label = label
    run_end_time = end_time
    run_end_cycle = end_cycle
    print_interval = DEFAULT_INTERVAL
    if (present(interval)) print_interval = interval
    step_word = 'cycle'
    if (present(word)) step_word = word
    wall_start = comm_wtime()
    wall_first = 0.0_wp
    wall_last_print = 0.0_wp
    fraction_first = 0.0_wp
    last_decile = -1
    updated = .false.
    first_cycle = 0
    last_cycle = 0
    last_time = 0.0_wp
    wall_previous = 0.0_wp
    cycle_counts = 0
    active = .true.
  end subroutine progress_start

  !> Note the state after a cycle; print a progress line when one is due (rank 0).
  subroutine progress_update(cycle, time, dt, printed, final)
    integer, intent(in) :: cycle                  !< cycle or step just completed
    real(wp), intent(in) :: time                  !< simulation time reached
    real(wp), intent(in) :: dt                    !< current time step
    logical, intent(out), optional :: printed     !< true when a line was printed
    logical, intent(in), optional :: final        !< the run's last: a line in any case
    real(wp) :: wall, fraction, eta
    integer :: decile
    logical :: due
    if (present(printed)) printed = .false.
    if (.not. (active .and. comm_is_root())) return
    wall = comm_wtime() - wall_start
    associate (bin => cycle_time_bin(wall - wall_previous))
      cycle_counts(bin) = cycle_counts(bin) + 1
    end associate
    wall_previous = wall
    fraction = progress_fraction(cycle, time, run_end_time, run_end_cycle)
    due = .not. updated
    if (due) then
      updated = .true.
      first_cycle = cycle
      wall_first = wall
      fraction_first = fraction
    end if
    last_cycle = cycle
    last_time = time
    decile = -1
    ! (a time that lands on a tenth of ENDTIM to round-off counts as reaching it)
    if (fraction >= 0.0_wp) decile = int(10.0_wp*fraction + DECILE_TOLERANCE)
    due = due .or. decile > last_decile .or. wall - wall_last_print >= print_interval
    if (present(final)) due = due .or. final
    if (.not. due) return
    last_decile = max(last_decile, decile)
    wall_last_print = wall
    eta = -1.0_wp
    if (fraction >= 0.0_wp .and. fraction > fraction_first .and. wall > wall_first) then
      eta = (1.0_wp - fraction) * (wall - wall_first) / (fraction - fraction_first)
    end if
    call say(trim(run_label)//': '// &
             trim(progress_line(cycle, time, dt, fraction, wall, eta, step_word)))
    if (present(printed)) printed = .true.
  end subroutine progress_update

  !> Print the summary of the run (call on every rank): wall time, cycles, time reached,
  !> wall time per cycle (mean; 5, 50 and 95 % percentiles) and peak memory (this rank's
  !> and the maximum over ranks).
  subroutine progress_finish()
    real(wp) :: memory, memory_max, wall, per_cycle
    integer :: cycles
    character(len=200) :: text
    memory = peak_memory_mib()
    memory_max = memory
    call comm_max(memory_max)
    if (.not. (active .and. comm_is_root())) then
      active = .false.
      return
    end if
    wall = comm_wtime() - wall_start
    cycles = 0
    if (updated) cycles = last_cycle - first_cycle + 1
    call say(trim(run_label)//': done, wall time '//trim(format_seconds(wall))//' ('// &
             decimal_text(wall)//' s)')
    write(text, '(a,1x,i0,a,i0,a,i0,a,es12.5)') trim(step_word)//'s', cycles, ' (', &
        first_cycle, ' to ', last_cycle, '), time reached', last_time
    call say(trim(run_label)//': '//trim(text))
    if (cycles > 0) then
      per_cycle = wall / real(cycles, wp)
      write(text, '(a,es10.3,a)') 'average wall time per '//trim(step_word)//' ', per_cycle, ' s'
      call say(trim(run_label)//': '//trim(text))
      write(text, '(a,3(es10.3,a))') 'wall time per '//trim(step_word)//', 5 / 50 / 95 % of '// &
          trim(step_word)//'s below ', cycle_time_percentile(cycle_counts, 5.0_wp), ' /', &
          cycle_time_percentile(cycle_counts, 50.0_wp), ' /', &
          cycle_time_percentile(cycle_counts, 95.0_wp), ' s'
      call say(trim(run_label)//': '//trim(text))
    end if
    call say(trim(run_label)//': peak memory '//decimal_text(memory)//' MiB on rank 0, '// &
             decimal_text(memory_max)//' MiB max over ranks')
    active = .false.
  end subroutine progress_finish

  !> Histogram bin of a cycle's wall time (s): k with CYCLE_TIME_LOW*CYCLE_BIN_RATIO**(k-1)
  !> <= seconds < CYCLE_TIME_LOW*CYCLE_BIN_RATIO**k, clipped to 1..CYCLE_BINS (a time below
  !> the lowest edge, zero or not a number goes to bin 1).
  pure integer function cycle_time_bin(seconds) result(bin)
    real(wp), intent(in) :: seconds     !< wall time of one cycle
    real(wp) :: position
    bin = 1
    if (.not. (seconds > CYCLE_TIME_LOW)) return
    position = log(seconds/CYCLE_TIME_LOW)/log(CYCLE_BIN_RATIO)
    if (position >= real(CYCLE_BINS - 1, wp)) then
      bin = CYCLE_BINS
    else
      bin = 1 + int(position)
    end if
  end function cycle_time_bin

  !> The p % percentile of the cycle times counted in a histogram of cycle_time_bin bins:
  !> the upper edge of the first bin at which the cumulated count reaches p % of the total
  !> (so at most CYCLE_BIN_RATIO - 1 above the exact percentile); 0 when nothing is counted.
  pure real(wp) function cycle_time_percentile(counts, percent) result(seconds)
    integer, intent(in) :: counts(CYCLE_BINS)  !< cycles per bin
    real(wp), intent(in) :: percent             !< p in [0, 100]
    real(wp) :: wanted
    integer :: bin, total, cumulated
    seconds = 0.0_wp
    total = sum(counts)
    if (total == 0) return
    wanted = max(percent, 0.0_wp)/100.0_wp*real(total, wp)
    cumulated = 0
    do bin = 1, CYCLE_BINS
      cumulated = cumulated + counts(bin)
      if (counts(bin) > 0 .and. real(cumulated, wp) >= wanted) exit
    end do
    bin = min(bin, CYCLE_BINS)
    seconds = CYCLE_TIME_LOW*CYCLE_BIN_RATIO**bin
  end function cycle_time_percentile

  !> A non-negative number with one decimal and no leading blanks, e.g. "0.5", "3723.4".
  pure function decimal_text(value) result(text)
    real(wp), intent(in) :: value   !< the number
    character(len=:), allocatable :: text
    character(len=24) :: buffer
    write(buffer, '(f24.1)') value
    text = trim(adjustl(buffer))
  end function decimal_text

  !> Fraction of the run done: time/end_time or cycle/end_cycle, whichever is larger,
  !> clipped to [0, 1]; -1 when neither end is given.
  pure real(wp) function progress_fraction(cycle, time, end_time, end_cycle)
    integer, intent(in) :: cycle        !< cycle reached
    real(wp), intent(in) :: time        !< time reached
    real(wp), intent(in) :: end_time    !< end time (<= 0: none)
    integer, intent(in) :: end_cycle    !< last cycle (<= 0: none)
    progress_fraction = -1.0_wp
    if (end_time > 0.0_wp) progress_fraction = time / end_time
    if (end_cycle > 0) progress_fraction = max(progress_fraction, &
                                               real(cycle, wp) / real(end_cycle, wp))
    if (end_time > 0.0_wp .or. end_cycle > 0) then
      progress_fraction = min(max(progress_fraction, 0.0_wp), 1.0_wp)
    end if
  end function progress_fraction

  !> Text of one progress line, e.g.
  !> "cycle 1200  t 1.2000E-03  dt 1.000E-06   12.0 %  wall 3.2s  eta 23s".
  !> A negative fraction leaves out the percentage and the ETA; a negative eta prints "eta --".
  pure function progress_line(cycle, time, dt, fraction, wall, eta, word) result(line)
    integer, intent(in) :: cycle                    !< cycle or step number
    real(wp), intent(in) :: time                    !< simulation time
    real(wp), intent(in) :: dt                      !< time step
    real(wp), intent(in) :: fraction                !< fraction done in [0, 1], or < 0
    real(wp), intent(in) :: wall                    !< wall time used so far (s)
    real(wp), intent(in) :: eta                     !< estimated wall time left (s), or < 0
    character(len=*), intent(in), optional :: word  !< "cycle" (default) or "step"
    character(len=PROGRESS_LINE_LENGTH) :: line
    integer :: position
    line = ''
    if (present(word)) then
      write(line, '(a,1x,i0)') trim(word), cycle
    else
      write(line, '(a,1x,i0)') 'cycle', cycle
    end if
    position = len_trim(line) + 1
    write(line(position:), '(a,es11.4,a,es10.3)') '  t ', time, '  dt ', dt
    if (fraction >= 0.0_wp) then
      position = len_trim(line) + 1
      write(line(position:), '(2x,f5.1,a)') 100.0_wp*fraction, ' %'
    end if
    position = len_trim(line) + 1
    line(position:) = '  wall '//format_seconds(wall)
    if (fraction >= 0.0_wp) then
      position = len_trim(line) + 1
      if (eta >= 0.0_wp) then
        line(position:) = '  eta '//format_seconds(eta)
      else
        line(position:) = '  eta --'
      end if
    end if
  end function progress_line

  !> A duration as short text: "3.2s", "45s", "2m05s", "1h02m03s", "2d03h04m"; "--" when
  !> negative or not a number. The result has trailing blanks.
  pure function format_seconds(seconds) result(text)
    real(wp), intent(in) :: seconds     !< duration in seconds
    character(len=SECONDS_TEXT_LENGTH) :: text
    integer(int64) :: total, days, hours, minutes, secs
    text = '--'
    if (.not. (seconds >= 0.0_wp)) return   ! negative or NaN
    if (seconds >= 8.64e9_wp) then          ! more than 100000 days
      text = '>99999d'
      return
    end if
    if (seconds < 9.95_wp) then
      write(text, '(f3.1,a)') seconds, 's'
      return
    end if
    total = nint(seconds, int64)
    days = total / 86400_int64
    hours = mod(total, 86400_int64) / 3600_int64
    minutes = mod(total, 3600_int64) / 60_int64
    secs = mod(total, 60_int64)
    if (days > 0) then
      write(text, '(i0,a,i2.2,a,i2.2,a)') days, 'd', hours, 'h', minutes, 'm'
    else if (hours > 0) then
      write(text, '(i0,a,i2.2,a,i2.2,a)') hours, 'h', minutes, 'm', secs, 's'
    else if (minutes > 0) then
      write(text, '(i0,a,i2.2,a)') minutes, 'm', secs, 's'
    else
      write(text, '(i0,a)') secs, 's'
    end if
  end function format_seconds

  !> Peak resident memory of this process in MiB (VmHWM of /proc/self/status); 0 when unknown.
  real(wp) function peak_memory_mib()
    integer :: unit, ios
    character(len=256) :: line
    real(wp) :: kibibytes
    peak_memory_mib = 0.0_wp
    open(newunit=unit, file='/proc/self/status', status='old', action='read', iostat=ios)
    if (ios /= 0) return
    do
      read(unit, '(a)', iostat=ios) line
      if (ios /= 0) exit
      if (line(1:6) == 'VmHWM:') then
        read(line(7:), *, iostat=ios) kibibytes
        if (ios == 0) peak_memory_mib = kibibytes / 1024.0_wp
        exit
      end if
    end do
    close(unit)
  end function peak_memory_mib

end module mefem_progress
