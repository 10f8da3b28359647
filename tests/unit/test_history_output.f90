!> Unit test of the LS-DYNA-style glstat and nodout writers: write 3 glstat records and a
!> nodout of 2 nodes x 3 steps, read both files back and compare values, labels and layout;
!> check that only rank 0 writes and that appending after a restart keeps one banner.
! ranks: 1 2
program test_history_output
  use mefem_kinds, only: wp
  use mefem_comm, only: comm_rank, comm_size, comm_is_root, comm_barrier
  use mefem_testing, only: test_start, test_finish, check, check_close, check_equal, project_root
  use mefem_history_output, only: glstat_record_t, glstat_open, glstat_write, glstat_close, &
      glstat_is_open, glstat_total_energy, glstat_energy_ratio, nodout_open, nodout_write, &
      nodout_close, nodout_is_open
  implicit none

  integer, parameter :: NREC = 3             !< glstat records and nodout steps written
  integer, parameter :: NNODE = 2            !< history nodes
  integer, parameter :: NLABEL = 21          !< value lines per glstat record
  integer, parameter :: MAX_LINES = 400      !< lines read back from one file
  real(wp), parameter :: RTOL = 1.0e-10_wp   !< 12 significant digits are printed
  character(len=*), parameter :: LABELS(NLABEL) = [character(len=32) :: 'time', 'time step', &
      'kinetic energy', 'internal energy', 'stonewall energy', 'spring and damper energy', &
      'hourglass energy', 'system damping energy', 'sliding interface energy', &
      'external work', 'eroded kinetic energy', 'eroded internal energy', &
      'eroded hourglass energy', 'total energy', 'total energy / initial energy', &
      'energy ratio w/o eroded energy', 'global x velocity', 'global y velocity', &
      'global z velocity', 'added mass', 'percentage increase']

  type(glstat_record_t) :: recs(NREC)
  character(len=:), allocatable :: dir
  character(len=512) :: lines(MAX_LINES)
  integer :: nlines, r
  integer :: node_ids(NNODE) = [101, 2000000007]
  real(wp) :: disp(3, NNODE, NREC), vel(3, NNODE, NREC), acc(3, NNODE, NREC)
  real(wp) :: coor(3, NNODE, NREC)
  logical :: exists

  call test_start('history_output')
  dir = output_dir()
  if (comm_is_root()) then
    call execute_command_line('rm -rf '//dir//' && mkdir -p '//dir)
    do r = 0, comm_size() - 1
      call execute_command_line('mkdir -p '//dir//'/rank'//itoa(r))
    end do
  end if
  call comm_barrier()

  call make_records()
  call make_nodal_data()

  ! energy helpers: LS-DYNA's definitions
  call check_close(glstat_total_energy(recs(2)), 10.0_wp + 100.0_wp + 3.0_wp + 4.0_wp + &
      0.5_wp + 0.25_wp, RTOL, 'total energy = KE+IE+contact+hourglass+damping+rigid wall')
  call check_close(glstat_energy_ratio(110.0_wp, 100.0_wp, 10.0_wp), 1.0_wp, RTOL, &
      'energy ratio = total / (initial + external work)')
  call check_close(glstat_energy_ratio(90.0_wp, 50.0_wp, 50.0_wp), 0.9_wp, RTOL, &
      'energy ratio below 1 when energy is lost')
  call check_close(glstat_energy_ratio(0.0_wp, 0.0_wp, 0.0_wp), 1.0_wp, RTOL, &
      'energy ratio is 1 before any energy exists')

  ! only rank 0 writes: every rank names its own directory, only rank0/ gets files
  call glstat_open(dir//'/rank'//itoa(comm_rank()))
  call nodout_open(dir//'/rank'//itoa(comm_rank()), node_ids)
  call check(glstat_is_open() .eqv. comm_is_root(), 'glstat is open on rank 0 only')
  call check(nodout_is_open() .eqv. comm_is_root(), 'nodout is open on rank 0 only')
  call glstat_write(recs(1))
  call nodout_write(recs(1)%cycle, recs(1)%time, disp(:, :, 1), vel(:, :, 1), acc(:, :, 1), &
                    coor(:, :, 1))
  call glstat_close()
  call nodout_close()
  call comm_barrier()
  inquire(file=dir//'/rank0/glstat', exist=exists)
  call check(exists, 'rank 0 wrote glstat')
  inquire(file=dir//'/rank0/nodout', exist=exists)
  call check(exists, 'rank 0 wrote nodout')
  do r = 1, comm_size() - 1
    inquire(file=dir//'/rank'//itoa(r)//'/glstat', exist=exists)
    call check(.not. exists, 'rank '//itoa(r)//' wrote no glstat')
    inquire(file=dir//'/rank'//itoa(r)//'/nodout', exist=exists)
    call check(.not. exists, 'rank '//itoa(r)//' wrote no nodout')
  end do

  ! restart: appending adds records without a second banner
  call glstat_open(dir//'/rank0', append=.true.)
  call glstat_write(recs(2))
  call glstat_close()
  call comm_barrier()
  call read_lines(dir//'/rank0/glstat', lines, nlines)
  call check_equal(count_prefix(' dt of cycle'), 2, 'appended glstat has 2 records')
  call check_equal(count_containing(' date '), 1, 'appended glstat has one banner')

  ! the files of the test: 3 glstat records, 2 nodes x 3 nodout steps
  call glstat_open(dir, title='history unit test')
  call nodout_open(dir, node_ids, title='history unit test')
  do r = 1, NREC
    call glstat_write(recs(r))
    call nodout_write(recs(r)%cycle, recs(r)%time, disp(:, :, r), vel(:, :, r), &
                      acc(:, :, r), coor(:, :, r))
  end do
  call glstat_close()
  call nodout_close()
  call comm_barrier()

  call check_glstat()
  call check_nodout()
  call test_finish()

contains

  !> tests/out/history_unit/np<N> of the project.
  function output_dir() result(path)
    character(len=:), allocatable :: path
    path = project_root()//'/tests/out/history_unit/np'//itoa(comm_size())
  end function output_dir

  !> Decimal text of an integer.
  function itoa(value) result(text)
    integer, intent(in) :: value   !< the integer
    character(len=:), allocatable :: text
    character(len=16) :: buffer
    write(buffer, '(i0)') value
    text = trim(buffer)
  end function itoa

  !> Three records with distinct values, negative numbers and 3-digit exponents.
  subroutine make_records()
    integer :: k
    do k = 1, NREC
      recs(k)%cycle = 5 + 1000*(k - 1)
      recs(k)%time = 1.0e-3_wp*real(k - 1, wp) + 1.0e-9_wp/3.0_wp
      recs(k)%time_step = 2.123456789012e-7_wp*real(k, wp)
      recs(k)%kinetic_energy = 10.0_wp*real(k - 1, wp)
      recs(k)%internal_energy = 100.0_wp*real(k - 1, wp)**2
      recs(k)%external_work = 7.0_wp/3.0_wp*real(k, wp)
      recs(k)%contact_energy = 1.5_wp*real(k, wp)
      recs(k)%hourglass_energy = 2.0_wp*real(k, wp)
      recs(k)%damping_energy = 0.25_wp*real(k, wp)
      recs(k)%rigidwall_energy = 0.125_wp*real(k, wp)
      recs(k)%added_mass = 1.0e-120_wp*real(k, wp)
      recs(k)%percent_mass_increase = 3.3e+150_wp*real(k, wp)
      recs(k)%total_energy = glstat_total_energy(recs(k))
      recs(k)%energy_ratio = glstat_energy_ratio(recs(k)%total_energy, &
          recs(1)%total_energy, recs(k)%external_work)
      recs(k)%eroded_internal_energy = 0.75_wp*real(k, wp)
      recs(k)%energy_ratio_uneroded = glstat_energy_ratio(recs(k)%total_energy + &
          recs(k)%eroded_internal_energy, recs(1)%total_energy, recs(k)%external_work)
      recs(k)%global_velocity = [-1.0_wp/7.0_wp, 0.0_wp, 123456.789_wp]*real(k, wp)
    end do
    recs(1)%controlled_by = 'solid 123 of part 1'
    recs(2)%controlled_by = 'load curve'
    recs(3)%controlled_by = 'shell 7 of part 22'
  end subroutine make_records

  !> Nodal values that differ per component, node and step.
  subroutine make_nodal_data()
    integer :: i, n, k
    do k = 1, NREC
      do n = 1, NNODE
        do i = 1, 3
          disp(i, n, k) = 1.0e-3_wp*real(i + 10*n + 100*k, wp)/3.0_wp
          vel(i, n, k) = -2.5e2_wp*real(i*n, wp)/real(k, wp)
          acc(i, n, k) = 1.0e7_wp*real(i - 2, wp)*real(k, wp)/7.0_wp
          coor(i, n, k) = 0.1_wp*real(i + n, wp) + disp(i, n, k)
        end do
      end do
    end do
  end subroutine make_nodal_data

  !> Read a text file into lines (all ranks; the files are written before a barrier).
  subroutine read_lines(path, text, n)
    character(len=*), intent(in) :: path        !< file to read
    character(len=*), intent(out) :: text(:)    !< its lines
    integer, intent(out) :: n                   !< number of lines read
    integer :: unit, ios
    n = 0
    text = ''
    open(newunit=unit, file=path, status='old', action='read', iostat=ios)
    call check(ios == 0, 'open '//path)
    if (ios /= 0) return
    do
      if (n == size(text)) exit
      read(unit, '(a)', iostat=ios) text(n + 1)
      if (ios /= 0) exit
      n = n + 1
    end do
    close(unit)
  end subroutine read_lines

  !> Number of lines read that start with the prefix.
  integer function count_prefix(prefix)
    character(len=*), intent(in) :: prefix   !< leading text
    integer :: i
    count_prefix = 0
    do i = 1, nlines
      if (lines(i)(1:len(prefix)) == prefix) count_prefix = count_prefix + 1
    end do
  end function count_prefix

  !> Number of lines read that contain the text.
  integer function count_containing(text)
    character(len=*), intent(in) :: text   !< text searched for
    integer :: i
    count_containing = 0
    do i = 1, nlines
      if (index(lines(i), text) > 0) count_containing = count_containing + 1
    end do
  end function count_containing

  !> Number of blank-separated tokens of a line.
  integer function token_count(line)
    character(len=*), intent(in) :: line   !< the line
    integer :: i
    token_count = 0
    do i = 1, len_trim(line)
      if (line(i:i) /= ' ' .and. (i == 1)) then
        token_count = token_count + 1
      else if (i > 1) then
        if (line(i:i) /= ' ' .and. line(i-1:i-1) == ' ') token_count = token_count + 1
      end if
    end do
  end function token_count

  !> The values of a record in the order of LABELS.
  function record_values(rec) result(values)
    type(glstat_record_t), intent(in) :: rec   !< the record
    real(wp) :: values(NLABEL)
    values = [rec%time, rec%time_step, rec%kinetic_energy, rec%internal_energy, &
        rec%rigidwall_energy, 0.0_wp, rec%hourglass_energy, rec%damping_energy, &
        rec%contact_energy, rec%external_work, 0.0_wp, rec%eroded_internal_energy, 0.0_wp, &
        rec%total_energy, rec%energy_ratio, rec%energy_ratio_uneroded, rec%global_velocity, rec%added_mass, &
        rec%percent_mass_increase]
  end function record_values

  !> Read glstat back: banner, 3 blocks, each with every label once and the written values.
  subroutine check_glstat()
    real(wp) :: got(NLABEL, NREC), value
    integer :: seen(NLABEL, NREC), block, i, j, k, ios, cycles(NREC)
    character(len=32) :: label
    logical :: labels_ok, columns_ok, split_ok
    call read_lines(dir//'/glstat', lines, nlines)
    call check(lines(1) == ' history unit test', 'glstat line 1 is the title')
    call check(index(lines(2), 'mefem') > 0 .and. index(lines(2), 'date ') > 0, &
               'glstat line 2 names the program and the date')
    call check_equal(count_prefix(' dt of cycle'), NREC, 'glstat has 3 "dt of cycle" blocks')
    call check_equal(count_prefix(' time step......................'), NREC, &
                     'glstat has 3 "time step" lines with LS-DYNA label text')
    call check_equal(count_prefix(' hourglass energy ..............'), NREC, &
                     'glstat hourglass label as LS-DYNA writes it')
    call check_equal(count_prefix(' total energy / initial energy..'), NREC, &
                     'glstat energy ratio label as LS-DYNA writes it')
    call check_equal(count_containing(' date '), 1, 'glstat has one banner')
    got = 0.0_wp
    seen = 0
    cycles = -1
    block = 0
    labels_ok = .true.
    columns_ok = .true.
    split_ok = .true.
    do i = 3, nlines
      if (lines(i)(1:12) == ' dt of cycle') then
        block = block + 1
        if (block > NREC) exit
        read(lines(i)(13:20), *, iostat=ios) cycles(block)
        cycle
      end if
      if (len_trim(lines(i)) == 0 .or. block == 0) cycle
      ! " label......" up to column 32, the value after it
      label = lines(i)(2:32)
      k = len_trim(label)
      do while (k > 0)
        if (label(k:k) /= '.') exit
        k = k - 1
      end do
      label = adjustl(label(1:k))
      j = findloc_label(label)
      if (j == 0) then
        labels_ok = .false.
        cycle
      end if
      columns_ok = columns_ok .and. lines(i)(33:33) == ' ' .and. lines(i)(32:32) == '.'
      read(lines(i)(33:), *, iostat=ios) value
      if (ios /= 0) columns_ok = .false.
      split_ok = split_ok .and. token_count(lines(i)(33:)) == 1
      got(j, block) = value
      seen(j, block) = seen(j, block) + 1
    end do
    call check(labels_ok, 'glstat has no unknown labels')
    call check(all(seen == 1), 'glstat: every label exactly once per record')
    call check(columns_ok, 'glstat values start after column 32, separated by a blank')
    call check(split_ok, 'glstat value is the single token after the label')
    do k = 1, NREC
      call check_equal(cycles(k), recs(k)%cycle, 'glstat cycle of record '//itoa(k))
      call check_close(got(:, k), record_values(recs(k)), RTOL, &
                       'glstat values of record '//itoa(k)//' read back', atol=1.0e-300_wp)
    end do
    i = first_prefix(' dt of cycle')
    call check(lines(i) == ' dt of cycle       5 is controlled by solid            123'// &
               ' of part         1', 'glstat controlling element in LS-DYNA columns', &
               trim(lines(i)))
    call check_equal(count_containing(' dt of cycle    1005 is controlled by load curve'), 1, &
                     'glstat free controlling text written as given')
    call check_equal(count_containing(' dt of cycle    2005 is controlled by shell'// &
                     '              7 of part        22'), 1, 'glstat third controlling element')
  end subroutine check_glstat

  !> Index in LABELS of a label text, 0 when unknown.
  integer function findloc_label(label)
    character(len=*), intent(in) :: label   !< label without dots
    integer :: j
    findloc_label = 0
    do j = 1, NLABEL
      if (trim(LABELS(j)) == trim(label)) findloc_label = j
    end do
  end function findloc_label

  !> Index of the first line read that starts with the prefix (0 when none).
  integer function first_prefix(prefix)
    character(len=*), intent(in) :: prefix   !< leading text
    integer :: i
    first_prefix = 0
    do i = nlines, 1, -1
      if (lines(i)(1:len(prefix)) == prefix) first_prefix = i
    end do
  end function first_prefix

  !> Read nodout back: banner, legend, 3 blocks of 2 rows with the written values.
  subroutine check_nodout()
    character(len=*), parameter :: header = &
        ' n o d a l   p r i n t   o u t   f o r   t i m e  s t e p'
    integer :: i, k, n, ios, step, id, blocks, rows_ok, tokens_ok
    real(wp) :: time, row(12), want(12)
    call read_lines(dir//'/nodout', lines, nlines)
    call check(lines(1) == ' history unit test', 'nodout line 1 is the title')
    i = first_prefix('{BEGIN LEGEND}')
    call check(i > 0, 'nodout has a legend')
    if (i > 0) then
      call check(index(lines(i + 1), 'Entity #') > 0, 'nodout legend header')
      do n = 1, NNODE
        read(lines(i + 1 + n), *, iostat=ios) id
        call check(ios == 0 .and. id == node_ids(n), 'nodout legend lists node '//itoa(n))
      end do
      call check(lines(i + 2 + NNODE) == '{END LEGEND}', 'nodout legend ends')
    end if
    call check_equal(count_prefix(header), NREC, 'nodout has 3 "nodal print out" blocks')
    call check_equal(count_prefix(' nodal point  x-disp'), NREC, 'nodout column headers')
    blocks = 0
    rows_ok = 0
    tokens_ok = 0
    do i = 1, nlines
      if (lines(i)(1:len(header)) /= header) cycle
      blocks = blocks + 1
      k = blocks
      if (k > NREC) exit
      read(lines(i)(len(header) + 1:), *, iostat=ios) step
      call check(ios == 0 .and. step == recs(k)%cycle, 'nodout step of block '//itoa(k))
      read(lines(i)(index(lines(i), 'at time') + 7:), *, iostat=ios) time
      call check(ios == 0, 'nodout time of block '//itoa(k)//' readable')
      call check_close(time, recs(k)%time, RTOL, 'nodout time of block '//itoa(k))
      call check(len_trim(lines(i + 1)) == 0 .and. &
                 lines(i + 2)(1:20) == ' nodal point  x-disp' .and. &
                 index(lines(i + 2), 'z-coor') > 0, 'nodout block '//itoa(k)//' layout')
      do n = 1, NNODE
        read(lines(i + 2 + n), *, iostat=ios) id, row
        want = [disp(:, n, k), vel(:, n, k), acc(:, n, k), coor(:, n, k)]
        if (ios == 0 .and. id == node_ids(n) .and. &
            all(abs(row - want) <= RTOL*abs(want))) rows_ok = rows_ok + 1
        if (token_count(lines(i + 2 + n)) == 13) tokens_ok = tokens_ok + 1
      end do
    end do
    call check_equal(rows_ok, NREC*NNODE, 'nodout rows read back (id + 12 values, 1e-10)')
    call check_equal(tokens_ok, NREC*NNODE, 'nodout rows split into 13 tokens')
  end subroutine check_nodout

end program test_history_output
