!> LS-DYNA-style ASCII time-history files: glstat (global statistics) and nodout (history nodes).
!>
!> Only rank 0 writes; the caller passes global values already reduced over ranks, and every
!> routine returns at once on the other ranks. Each record is flushed as soon as it is written,
!> so the files are complete and readable after every record even if the run dies later.
!>
!> glstat layout (as written by LS-DYNA's ASCII glstat, established from real glstat files of
!> two LS-DYNA smp versions, revision 123264 and R16.1, and from LSTC's binout-to-ASCII tool):
!>
!>    <title>                                    line 1, one leading blank
!>                             mefem                  date mm/dd/yyyy
!>    (two blank lines before every record)
!>     dt of cycle<i8> is controlled by <type, a10><element, i10> of part<part, i10>
!>    (blank line)
!>     time...........................   1.00000000000E-003
!>     ...                               (label padded with dots to column 32, then the value)
!>
!> Record lines, in LS-DYNA's order: time, time step, kinetic energy, internal energy, stonewall
!> energy, spring and damper energy, hourglass energy, system damping energy, sliding interface
!> energy, external work, eroded kinetic/internal/hourglass energy, total energy,
!> total energy / initial energy, energy ratio w/o eroded energy, global x/y/z velocity, then
!> (after two blank lines) added mass and percentage increase.
!>
!> Energy definitions (LS-DYNA's; see dynasupport.com "Total energy" and "Energy data"):
!>   total energy = kinetic + internal + sliding interface (contact) + hourglass
!>                  + system damping + stonewall (rigid wall) energy;
!>   "total energy / initial energy" is, despite its label,
!>                  total energy / (initial total energy + external work),
!>   so 1 means perfect balance. glstat_total_energy and glstat_energy_ratio compute these.
!>
!> Deviations from LS-DYNA, kept small so that label-based scripts still work:
!>  - numbers carry 12 significant digits with a 3-digit exponent (ES21.11E3 in glstat,
!>    ES20.11E3 in nodout) instead of LS-DYNA's 6 (glstat, 1PE14.5) or 5 (nodout, 1PE12.4).
!>    Every value is separated from its neighbour by at least one blank, so splitting on
!>    whitespace and label/regex parsers work; scripts that cut fixed LS-DYNA columns do not;
!>  - "stonewall energy" is the total over all rigid walls, written on every record without
!>    LS-DYNA's per-wall " wall#  n" suffix; hourglass, system damping, stonewall energy, added
!>    mass and percentage increase are always written (LS-DYNA writes them only when HGEN,
!>    RYLEN, RWEN or mass scaling ask for them);
!>  - mefem has no discrete elements and no erosion: "spring and damper energy" and the three
!>    "eroded ..." lines are always 0, and "energy ratio w/o eroded energy" equals the ratio;
!>  - not written: "time per zone cycle.(nanosec)", "dissipated kinetic/internal energy",
!>    "drilling energy" and the shell "minimum time step" count;
!>  - the controlling element text is reformatted to LS-DYNA's columns when it reads
!>    "<type> <element> of part <part>"; any other text (e.g. "load curve") is written as given.
!>
!> nodout layout: banner as in glstat, a {BEGIN LEGEND} ... {END LEGEND} block with the node ids,
!> then per record three blank lines,
!>     n o d a l   p r i n t   o u t   f o r   t i m e  s t e p<i8>    ( at time <t> )
!> a blank line, the column header " nodal point  x-disp  y-disp ... z-coor" and one row per
!> node: id (i10) followed by x/y/z displacement, velocity, acceleration and coordinate.
!> No rotation block (solids only). Units are those of the input deck.
module mefem_history_output
  use mefem_kinds, only: wp, i8
  use mefem_comm, only: comm_is_root
  use mefem_errors, only: fatal_local
  use mefem_text_file, only: text_open, text_put, text_flush, text_close
  use mefem_file_system, only: truncate_file, remove_file
  use mefem_restart_file, only: restart_file_t, restart_put_reals, restart_get_reals
  implicit none
  private

  public :: HISTORY_FILES, history_restart_put, history_restart_get

  !> The ASCII history files a run may write in its output directory
  character(len=6), parameter :: HISTORY_FILES(5) = [character(len=6) :: 'glstat', 'nodout', &
      'rcforc', 'rwforc', 'rbdout']

  public :: glstat_record_t
  public :: glstat_open, glstat_write, glstat_close, glstat_is_open
  public :: glstat_total_energy, glstat_energy_ratio
  public :: nodout_open, nodout_write, nodout_close, nodout_is_open
  public :: rwforc_open, rwforc_write, rwforc_close
  public :: rbdout_open, rbdout_write, rbdout_close
  public :: rcforc_open, rcforc_write, rcforc_close

  integer, parameter :: LABEL_WIDTH = 32        !< columns of " label......" before a value
  character(len=*), parameter :: GLSTAT_VALUE = 'es21.11e3'   !< glstat value edit descriptor
  character(len=*), parameter :: NODOUT_VALUE = 'es20.11e3'   !< nodout value edit descriptor
  character(len=*), parameter :: NODOUT_HEADER = &
      ' n o d a l   p r i n t   o u t   f o r   t i m e  s t e p'
  character(len=*), parameter :: DEFAULT_TITLE = 'mefem'

  !> One glstat record: global values of one output time, already reduced over all ranks.
  type :: glstat_record_t
    integer :: cycle = 0                         !< cycle (explicit) or step (implicit) number
    real(wp) :: time = 0.0_wp                    !< simulation time
    real(wp) :: time_step = 0.0_wp               !< current time step
    real(wp) :: kinetic_energy = 0.0_wp          !< kinetic energy
    real(wp) :: internal_energy = 0.0_wp         !< internal (strain) energy
    real(wp) :: external_work = 0.0_wp           !< work of loads and prescribed motions
    real(wp) :: contact_energy = 0.0_wp          !< sliding interface (contact) energy
    real(wp) :: hourglass_energy = 0.0_wp        !< hourglass energy
    real(wp) :: damping_energy = 0.0_wp          !< energy dissipated by system (mass) damping
    real(wp) :: rigidwall_energy = 0.0_wp        !< energy of all rigid walls (stonewalls)
    real(wp) :: added_mass = 0.0_wp              !< mass added by mass scaling
    real(wp) :: percent_mass_increase = 0.0_wp   !< added mass in % of the physical mass
    real(wp) :: total_energy = 0.0_wp            !< see glstat_total_energy
    real(wp) :: energy_ratio = 1.0_wp            !< see glstat_energy_ratio
    real(wp) :: eroded_internal_energy = 0.0_wp  !< internal energy of the eroded elements
    real(wp) :: energy_ratio_uneroded = 1.0_wp   !< the ratio with the eroded energy counted
    real(wp) :: global_velocity(3) = 0.0_wp      !< x, y, z velocity of the centre of mass
    character(len=80) :: controlled_by = ''      !< e.g. "solid 123 of part 1"
  end type glstat_record_t

  integer :: glstat_unit = -1                     !< handle of the open glstat file (mefem_text_file)
  logical :: glstat_opened = .false.
  character(len=:), allocatable :: glstat_path
  integer :: nodout_unit = -1                     !< handle of the open nodout file (mefem_text_file)
  logical :: nodout_opened = .false.
  character(len=:), allocatable :: nodout_path
  integer, allocatable :: nodout_ids(:)           !< user ids of the history nodes
  integer :: rcforc_unit = -1                     !< handle of the open rcforc file (mefem_text_file)
  logical :: rcforc_opened = .false.
  character(len=:), allocatable :: rcforc_path
  integer :: rbdout_unit = -1                     !< handle of the open rbdout file (mefem_text_file)
  logical :: rbdout_opened = .false.
  character(len=:), allocatable :: rbdout_path
  integer :: rwforc_unit = -1                     !< handle of the open rwforc file (mefem_text_file)
  logical :: rwforc_opened = .false.
  character(len=:), allocatable :: rwforc_path

contains

  !> Total energy as LS-DYNA defines it in glstat (external work is not part of it).
  pure real(wp) function glstat_total_energy(rec)
    type(glstat_record_t), intent(in) :: rec   !< record with the energy terms filled in
    glstat_total_energy = rec%kinetic_energy + rec%internal_energy + rec%contact_energy &
        + rec%hourglass_energy + rec%damping_energy + rec%rigidwall_energy
  end function glstat_total_energy

  !> LS-DYNA's energy ratio: total / (initial total + external work); 1 = perfect balance.
  !> When the denominator is exactly 0 (a run starting at rest, no work yet) the ratio is 1.
  pure real(wp) function glstat_energy_ratio(total_energy, initial_total_energy, external_work)
    real(wp), intent(in) :: total_energy          !< current total energy
    real(wp), intent(in) :: initial_total_energy  !< total energy of the first record
    real(wp), intent(in) :: external_work         !< external work done so far
    real(wp) :: denominator
    denominator = initial_total_energy + external_work
    if (abs(denominator) > 0.0_wp) then
      glstat_energy_ratio = total_energy / denominator
    else
      glstat_energy_ratio = 1.0_wp
    end if
  end function glstat_energy_ratio

  !> Open <dir>/glstat on rank 0 and write the banner (unless appending after a restart).
  subroutine glstat_open(dir, title, append)
    character(len=*), intent(in) :: dir              !< output directory (must exist)
    character(len=*), intent(in), optional :: title  !< run title for line 1 (default "mefem")
    logical, intent(in), optional :: append          !< continue an existing file (restart)
    logical :: appending
    if (.not. comm_is_root()) return
    if (glstat_opened) call glstat_close()
    appending = .false.
    if (present(append)) appending = append
    glstat_path = join_path(dir, 'glstat')
    call open_history(glstat_path, appending, glstat_unit)
    glstat_opened = .true.
    if (.not. appending) then
      if (present(title)) then
        call write_banner(glstat_unit, glstat_path, title)
      else
        call write_banner(glstat_unit, glstat_path, DEFAULT_TITLE)
      end if
    end if
    call flush_history(glstat_unit, glstat_path)
  end subroutine glstat_open

  !> True on the rank that has the glstat file open (rank 0 after glstat_open).
  logical function glstat_is_open()
    glstat_is_open = glstat_opened
  end function glstat_is_open

  !> Append one record to glstat and flush it.
  subroutine glstat_write(rec)
    type(glstat_record_t), intent(in) :: rec   !< global values of this output time
    integer :: u
    if (.not. comm_is_root()) return
    if (.not. glstat_opened) call fatal_local('glstat_write called before glstat_open')
    u = glstat_unit
    call put_line(u, '', glstat_path)
    call put_line(u, '', glstat_path)
    call put_line(u, trim(cycle_line(rec%cycle, rec%controlled_by)), glstat_path)
    call put_line(u, '', glstat_path)
    call write_value(u, 'time', rec%time)
    call write_value(u, 'time step', rec%time_step)
    call write_value(u, 'kinetic energy', rec%kinetic_energy)
    call write_value(u, 'internal energy', rec%internal_energy)
    call write_value(u, 'stonewall energy', rec%rigidwall_energy)
    call write_value(u, 'spring and damper energy', 0.0_wp)
    call write_value(u, 'hourglass energy ', rec%hourglass_energy)
    call write_value(u, 'system damping energy', rec%damping_energy)
    call write_value(u, 'sliding interface energy', rec%contact_energy)
    call write_value(u, 'external work', rec%external_work)
    call write_value(u, 'eroded kinetic energy', 0.0_wp)
    call write_value(u, 'eroded internal energy', rec%eroded_internal_energy)
    call write_value(u, 'eroded hourglass energy', 0.0_wp)
    call write_value(u, 'total energy', rec%total_energy)
    call write_value(u, 'total energy / initial energy', rec%energy_ratio)
    call write_value(u, 'energy ratio w/o eroded energy', rec%energy_ratio_uneroded)
    call write_value(u, 'global x velocity', rec%global_velocity(1))
    call write_value(u, 'global y velocity', rec%global_velocity(2))
    call write_value(u, 'global z velocity', rec%global_velocity(3))
    call put_line(u, '', glstat_path)
    call put_line(u, '', glstat_path)
    call write_value(u, 'added mass', rec%added_mass)
    call write_value(u, 'percentage increase', rec%percent_mass_increase)
    call flush_history(u, glstat_path)
  end subroutine glstat_write

  !> Close glstat (no-op when it is not open).
  subroutine glstat_close()
    if (.not. glstat_opened) return
    call close_history(glstat_unit, glstat_path)
    glstat_opened = .false.
    glstat_unit = -1
  end subroutine glstat_close

  !> Open <dir>/nodout on rank 0 for the given history nodes and write banner and legend.
  subroutine nodout_open(dir, node_ids, title, append)
    character(len=*), intent(in) :: dir              !< output directory (must exist)
    integer, intent(in) :: node_ids(:)               !< user ids of the history nodes, in order
    character(len=*), intent(in), optional :: title  !< run title for line 1 (default "mefem")
    logical, intent(in), optional :: append          !< continue an existing file (restart)
    logical :: appending
    integer :: i
    character(len=10) :: id_text
    if (.not. comm_is_root()) return
    if (nodout_opened) call nodout_close()
    appending = .false.
    if (present(append)) appending = append
    nodout_path = join_path(dir, 'nodout')
    nodout_ids = node_ids
    call open_history(nodout_path, appending, nodout_unit)
    nodout_opened = .true.
    if (.not. appending) then
      if (present(title)) then
        call write_banner(nodout_unit, nodout_path, title)
      else
        call write_banner(nodout_unit, nodout_path, DEFAULT_TITLE)
      end if
      call put_line(nodout_unit, '', nodout_path)
      call put_line(nodout_unit, '{BEGIN LEGEND}', nodout_path)
      call put_line(nodout_unit, ' Entity #        Title', nodout_path)
      do i = 1, size(nodout_ids)
        write(id_text, '(i10)') nodout_ids(i)
        call put_line(nodout_unit, id_text, nodout_path)
      end do
      call put_line(nodout_unit, '{END LEGEND}', nodout_path)
    end if
    call flush_history(nodout_unit, nodout_path)
  end subroutine nodout_open

  !> True on the rank that has the nodout file open (rank 0 after nodout_open).
  logical function nodout_is_open()
    nodout_is_open = nodout_opened
  end function nodout_is_open

  !> Append one nodout block (all history nodes at one time) and flush it.
  subroutine nodout_write(cycle, time, disp, vel, acc, coor)
    integer, intent(in) :: cycle          !< cycle or step number
    real(wp), intent(in) :: time          !< simulation time
    real(wp), intent(in) :: disp(:,:)     !< displacements (3, number of history nodes)
    real(wp), intent(in) :: vel(:,:)      !< velocities (3, n)
    real(wp), intent(in) :: acc(:,:)      !< accelerations (3, n)
    real(wp), intent(in) :: coor(:,:)     !< current coordinates (3, n)
    character(len=32) :: time_text
    character(len=40) :: row_format
    character(len=320) :: header
    character(len=256) :: row
    integer :: i, n
    if (.not. comm_is_root()) return
    if (.not. nodout_opened) call fatal_local('nodout_write called before nodout_open')
    n = size(nodout_ids)
    if (any(shape(disp) /= [3, n]) .or. any(shape(vel) /= [3, n]) .or. &
        any(shape(acc) /= [3, n]) .or. any(shape(coor) /= [3, n])) then
      call fatal_local('nodout_write: arrays must be (3, number of history nodes) for '// &
                       nodout_path)
    end if
    write(time_text, '('//NODOUT_VALUE//')') time
    do i = 1, 3
      call put_line(nodout_unit, '', nodout_path)
    end do
    call put_line(nodout_unit, NODOUT_HEADER//int_field(cycle, 8)//repeat(' ', 30)// &
                  '( at time '//trim(adjustl(time_text))//' )', nodout_path)
    header = nodout_column_header()
    call put_line(nodout_unit, '', nodout_path)
    call put_line(nodout_unit, trim(header), nodout_path)
    row_format = '(i10,12'//NODOUT_VALUE//')'
    do i = 1, n
      write(row, row_format) nodout_ids(i), disp(:, i), vel(:, i), acc(:, i), coor(:, i)
      call put_line(nodout_unit, trim(row), nodout_path)
    end do
    call flush_history(nodout_unit, nodout_path)
  end subroutine nodout_write

  !> Open <dir>/rwforc on rank 0 (rigid wall forces): banner, title and column header
  !> "time wall# normal-force x-force y-force z-force", one row per wall and output time.
  subroutine rwforc_open(dir, title, append)
    character(len=*), intent(in) :: dir              !< output directory (must exist)
    character(len=*), intent(in), optional :: title  !< run title for line 1 (default "mefem")
    logical, intent(in), optional :: append          !< continue an existing file (restart)
    if (.not. comm_is_root()) return
    if (rwforc_opened) call rwforc_close()
    rwforc_path = join_path(dir, 'rwforc')
    call open_table(rwforc_path, ' r i g i d   w a l l   f o r c e s', '                time'// &
        '   wall#        normal-force             x-force             y-force             '// &
        'z-force', rwforc_unit, title, append)
    rwforc_opened = .true.
  end subroutine rwforc_open

  !> Append one row per wall: the force the structure exerts on it and its normal part.
  subroutine rwforc_write(time, wall_ids, normal_force, force)
    real(wp), intent(in) :: time              !< simulation time
    integer, intent(in) :: wall_ids(:)        !< wall ids (RWID, or their order)
    real(wp), intent(in) :: normal_force(:)   !< (walls) force along the wall normal
    real(wp), intent(in) :: force(:,:)        !< (3, walls) force components
    character(len=128) :: row
    integer :: k
    if (.not. comm_is_root()) return
    if (.not. rwforc_opened) call fatal_local('rwforc_write called before rwforc_open')
    do k = 1, size(wall_ids)
      write(row, '('//NODOUT_VALUE//',i8,4'//NODOUT_VALUE//')') time, &
          merge(wall_ids(k), k, wall_ids(k) > 0), normal_force(k), force(:, k)
      call put_line(rwforc_unit, trim(row), rwforc_path)
    end do
    call flush_history(rwforc_unit, rwforc_path)
  end subroutine rwforc_write

  !> Close rwforc (no-op when it is not open).
  subroutine rwforc_close()
    if (.not. rwforc_opened) return
    call close_history(rwforc_unit, rwforc_path)
    rwforc_opened = .false.
    rwforc_unit = -1
  end subroutine rwforc_close

  !> Open <dir>/rbdout on rank 0 (rigid bodies): banner, title and column header; one row per
  !> body and output time: time, part id, centre displacement x y z, centre velocity x y z,
  !> reaction force x y z and reaction moment x y z (what constraints and prescribed motions
  !> apply to the body).
  subroutine rbdout_open(dir, title, append)
    character(len=*), intent(in) :: dir              !< output directory (must exist)
    character(len=*), intent(in), optional :: title  !< run title for line 1 (default "mefem")
    logical, intent(in), optional :: append          !< continue an existing file (restart)
    if (.not. comm_is_root()) return
    if (rbdout_opened) call rbdout_close()
    rbdout_path = join_path(dir, 'rbdout')
    call open_table(rbdout_path, ' r i g i d   b o d y   d a t a', '                time    part'// &
        '              x-disp              y-disp              z-disp'// &
        '               x-vel               y-vel               z-vel'// &
        '          x-reaction          y-reaction          z-reaction'// &
        '         xx-reaction         yy-reaction         zz-reaction', rbdout_unit, title, &
        append)
    rbdout_opened = .true.
  end subroutine rbdout_open

  !> Append one row per rigid body (values(12, bodies) in the column order of the header).
  subroutine rbdout_write(time, part_ids, values)
    real(wp), intent(in) :: time              !< simulation time
    integer, intent(in) :: part_ids(:)        !< part id of each body
    real(wp), intent(in) :: values(:,:)       !< (12, bodies)
    character(len=320) :: row
    integer :: k
    if (.not. comm_is_root()) return
    if (.not. rbdout_opened) call fatal_local('rbdout_write called before rbdout_open')
    do k = 1, size(part_ids)
      write(row, '('//NODOUT_VALUE//',i8,12'//NODOUT_VALUE//')') time, part_ids(k), values(:, k)
      call put_line(rbdout_unit, trim(row), rbdout_path)
    end do
    call flush_history(rbdout_unit, rbdout_path)
  end subroutine rbdout_write

  !> Close rbdout (no-op when it is not open).
  subroutine rbdout_close()
    if (.not. rbdout_opened) return
    call close_history(rbdout_unit, rbdout_path)
    rbdout_opened = .false.
    rbdout_unit = -1
  end subroutine rbdout_close

  !> Open <dir>/rcforc on rank 0 (contact resultants): banner and title as LS-DYNA's ASCII
  !> rcforc, then per interface and output time two lines (slave, master) of the form
  !>   "  slave        12 time  <t> x  <fx> y  <fy> z  <fz> mass  0 normal  <fn> tangential <ft>"
  !> (LS-DYNA's keywords and order; the normal and tangential magnitudes are mefem's own
  !> addition at the end of the line, for label-based parsers).
  subroutine rcforc_open(dir, title, append)
    character(len=*), intent(in) :: dir              !< output directory (must exist)
    character(len=*), intent(in), optional :: title  !< run title for line 1 (default "mefem")
    logical, intent(in), optional :: append          !< continue an existing file (restart)
    if (.not. comm_is_root()) return
    if (rcforc_opened) call rcforc_close()
    rcforc_path = join_path(dir, 'rcforc')
    call open_table(rcforc_path, ' r e s u l t a n t   i n t e r f a c e   f o r c e s', '', &
                    rcforc_unit, title, append)
    rcforc_opened = .true.
  end subroutine rcforc_open

  !> Create a history table on rank 0: banner (title or "mefem"), its spaced-out name and a
  !> column header (none when blank), flushed.
  subroutine open_table(path, name, header, unit, title, append)
    character(len=*), intent(in) :: path             !< file path
    character(len=*), intent(in) :: name             !< the table's spaced-out name line
    character(len=*), intent(in) :: header           !< column header ('' for none)
    integer, intent(out) :: unit                     !< the open file's handle
    character(len=*), intent(in), optional :: title  !< run title for line 1
    logical, intent(in), optional :: append          !< continue an existing file (restart)
    if (present(append)) then
      if (append) then
        call open_history(path, .true., unit)
        return
      end if
    end if
    call open_history(path, .false., unit)
    if (present(title)) then
      call write_banner(unit, path, title)
    else
      call write_banner(unit, path, DEFAULT_TITLE)
    end if
    call put_line(unit, '', path)
    call put_line(unit, name, path)
    call put_line(unit, '', path)
    if (len(header) > 0) call put_line(unit, header, path)
    call flush_history(unit, path)
  end subroutine open_table

  !> Append the slave and master resultants of one interface at one time.
  subroutine rcforc_write(time, interface_id, force_slave, force_master, normal_force, &
                          tangential_force)
    real(wp), intent(in) :: time                     !< simulation time
    integer, intent(in) :: interface_id              !< contact id
    real(wp), intent(in) :: force_slave(3)           !< sum of the slave side's nodal forces
    real(wp), intent(in) :: force_master(3)          !< sum of the master side's nodal forces
    real(wp), intent(in) :: normal_force             !< normal force magnitude
    real(wp), intent(in) :: tangential_force         !< tangential (friction) force magnitude
    character(len=*), parameter :: row = '(a,i10,a,'//NODOUT_VALUE//',3(a,'//NODOUT_VALUE// &
        '),a,'//NODOUT_VALUE//',a,'//NODOUT_VALUE//',a,'//NODOUT_VALUE//')'
    character(len=256) :: line
    if (.not. comm_is_root()) return
    if (.not. rcforc_opened) call fatal_local('rcforc_write called before rcforc_open')
    write(line, row) '  slave ', interface_id, ' time', time, ' x', &
        force_slave(1), ' y', force_slave(2), ' z', force_slave(3), ' mass', 0.0_wp, &
        ' normal', normal_force, ' tangential', tangential_force
    call put_line(rcforc_unit, trim(line), rcforc_path)
    write(line, row) '  master', interface_id, ' time', time, ' x', &
        force_master(1), ' y', force_master(2), ' z', force_master(3), ' mass', 0.0_wp, &
        ' normal', normal_force, ' tangential', tangential_force
    call put_line(rcforc_unit, trim(line), rcforc_path)
    call flush_history(rcforc_unit, rcforc_path)
  end subroutine rcforc_write

  !> Close rcforc (no-op when it is not open).
  subroutine rcforc_close()
    if (.not. rcforc_opened) return
    call close_history(rcforc_unit, rcforc_path)
    rcforc_opened = .false.
    rcforc_unit = -1
  end subroutine rcforc_close

  !> Close nodout (no-op when it is not open).
  subroutine nodout_close()
    if (.not. nodout_opened) return
    call close_history(nodout_unit, nodout_path)
    nodout_opened = .false.
    nodout_unit = -1
    if (allocated(nodout_ids)) deallocate(nodout_ids)
  end subroutine nodout_close

  ! ---- helpers ------------------------------------------------------------------------------

  !> "<dir>/<name>", or just the name when dir is blank.
  pure function join_path(dir, name) result(path)
    character(len=*), intent(in) :: dir    !< directory
    character(len=*), intent(in) :: name   !< file name
    character(len=:), allocatable :: path
    if (len_trim(dir) == 0) then
      path = name
    else if (dir(len_trim(dir):len_trim(dir)) == '/') then
      path = trim(dir)//name
    else
      path = trim(dir)//'/'//name
    end if
  end function join_path

  !> Open a history file for writing (replace or append; mefem_text_file, whose writes are
  !> checked); fatal on failure, naming the path and the system's reason.
  subroutine open_history(path, appending, unit)
    character(len=*), intent(in) :: path   !< file to open
    logical, intent(in) :: appending       !< keep the existing content and write after it
    integer, intent(out) :: unit           !< the file's handle
    logical :: ok
    character(len=:), allocatable :: message
    call text_open(path, appending, unit, ok, message)
    call stop_unless(ok, 'open', path, message)
  end subroutine open_history

  !> Write one line; a failure stops the run with the path and the system's reason.
  subroutine put_line(unit, text, path)
    integer, intent(in) :: unit             !< the file's handle
    character(len=*), intent(in) :: text    !< the line
    character(len=*), intent(in) :: path    !< its path, for the message
    logical :: ok
    character(len=:), allocatable :: message
    call text_put(unit, text, ok, message)
    call stop_unless(ok, 'write', path, message)
  end subroutine put_line

  !> Hand a history file's record to the system (each record reaches the file at once); a
  !> failure (a full disk shows here) stops the run with the system's reason.
  subroutine flush_history(unit, path)
    integer, intent(in) :: unit             !< the file's handle
    character(len=*), intent(in) :: path    !< its path, for the message
    logical :: ok
    character(len=:), allocatable :: message
    call text_flush(unit, ok, message)
    call stop_unless(ok, 'write', path, message)
  end subroutine flush_history

  !> Close a history file; a failure stops the run with the system's reason.
  subroutine close_history(unit, path)
    integer, intent(in) :: unit             !< the file's handle
    character(len=*), intent(in) :: path    !< its path, for the message
    logical :: ok
    character(len=:), allocatable :: message
    call text_close(unit, ok, message)
    call stop_unless(ok, 'close', path, message)
  end subroutine close_history

  !> Stop the run (this rank found it) unless ok: "cannot <action> history file <path>: <why>".
  subroutine stop_unless(ok, action, path, message)
    logical, intent(in) :: ok               !< the operation succeeded
    character(len=*), intent(in) :: action  !< open, write or close
    character(len=*), intent(in) :: path    !< the file
    character(len=*), intent(in) :: message !< the system's reason
    if (.not. ok) call fatal_local('cannot '//action//' history file '//path//': '//message)
  end subroutine stop_unless

  !> Banner of LS-DYNA's ASCII files: the title, then program name and date.
  subroutine write_banner(unit, path, title)
    integer, intent(in) :: unit             !< open history file's handle
    character(len=*), intent(in) :: path    !< its path, for error messages
    character(len=*), intent(in) :: title   !< run title (cut to 72 characters)
    character(len=8) :: today
    call date_and_time(date=today)
    call put_line(unit, ' '//title(1:min(len_trim(title), 72)), path)
    call put_line(unit, repeat(' ', 25)//'mefem'//repeat(' ', 26)//'date '// &
                  today(5:6)//'/'//today(7:8)//'/'//today(1:4), path)
  end subroutine write_banner

  !> One glstat line: " label......" to column 32, then the value.
  subroutine write_value(unit, label, value)
    integer, intent(in) :: unit             !< the glstat file's handle
    character(len=*), intent(in) :: label   !< label text (trailing blanks are kept)
    real(wp), intent(in) :: value           !< the value
    character(len=LABEL_WIDTH) :: text
    character(len=LABEL_WIDTH + 32) :: line
    text = repeat('.', LABEL_WIDTH)
    text(1:1 + len(label)) = ' '//label
    write(line, '(a,'//GLSTAT_VALUE//')') text, value
    call put_line(unit, trim(line), glstat_path)
  end subroutine write_value

  !> The " dt of cycle ... is controlled by ..." line, in LS-DYNA's columns when possible.
  function cycle_line(cycle, controlled_by) result(line)
    integer, intent(in) :: cycle                  !< cycle number
    character(len=*), intent(in) :: controlled_by !< "<type> <element> of part <part>" or text
    character(len=160) :: line
    character(len=32) :: kind, word_of, word_part
    integer :: element, part, ios
    kind = ''
    word_of = ''
    word_part = ''
    element = 0
    part = 0
    line = ' dt of cycle'//int_field(cycle, 8)//' is controlled by'
    read(controlled_by, *, iostat=ios) kind, element, word_of, word_part, part
    if (ios == 0 .and. word_of == 'of' .and. word_part == 'part' .and. len_trim(kind) <= 10) then
      write(line(len_trim(line) + 2:), '(a10,i10,a,i10)') kind, element, ' of part', part
    else if (len_trim(controlled_by) > 0) then
      line = trim(line)//' '//trim(adjustl(controlled_by))
    end if
  end function cycle_line

  !> An integer right-justified in at least `width` columns (wider when it needs more digits).
  pure function int_field(value, width) result(text)
    integer, intent(in) :: value   !< the integer
    integer, intent(in) :: width   !< minimum number of columns
    character(len=:), allocatable :: text
    character(len=16) :: digits
    write(digits, '(i0)') value
    text = repeat(' ', max(0, width - len_trim(digits)))//trim(digits)
  end function int_field

  !> Column header of a nodout block; each label starts 2 columns right of its field start.
  function nodout_column_header() result(header)
    character(len=320) :: header
    character(len=6), parameter :: names(12) = [character(len=6) :: 'x-disp', 'y-disp', &
        'z-disp', 'x-vel', 'y-vel', 'z-vel', 'x-accl', 'y-accl', 'z-accl', 'x-coor', &
        'y-coor', 'z-coor']
    integer :: k, start
    header = ' nodal point'
    do k = 1, 12
      start = 15 + 20*(k - 1)
      header(start:start + 5) = names(k)
    end do
  end function nodout_column_header

  !> Record the lengths of the history files in dir (rank 0; -1 for a file not there) into a
  !> restart file: a restart cuts them back to these lengths and goes on appending, so they
  !> read as if the run had never stopped.
  subroutine history_restart_put(f, dir)
    type(restart_file_t), intent(inout) :: f          !< file being written (rank 0 writes)
    character(len=*), intent(in) :: dir               !< output directory
    real(wp) :: bytes(size(HISTORY_FILES))
    integer(i8) :: length
    logical :: found
    integer :: k
    bytes = -1.0_wp
    if (comm_is_root()) then
      do k = 1, size(HISTORY_FILES)
        inquire(file=join_path(dir, trim(HISTORY_FILES(k))), exist=found, size=length)
        if (found) bytes(k) = real(length, wp)
      end do
    end if
    call restart_put_reals(f, 'histories.bytes', size(bytes), bytes)
  end subroutine history_restart_put

  !> Cut the history files in dir back to the lengths a restart file recorded (rank 0; a file
  !> that was not there then is removed); the histories are then opened for appending.
  subroutine history_restart_get(f, dir)
    type(restart_file_t), intent(inout) :: f          !< file being read
    character(len=*), intent(in) :: dir               !< output directory
    real(wp) :: bytes(size(HISTORY_FILES))
    logical :: ok
    integer :: k
    call restart_get_reals(f, 'histories.bytes', size(bytes), bytes)
    if (.not. comm_is_root()) return
    do k = 1, size(HISTORY_FILES)
      if (bytes(k) < 0.0_wp) then
        call remove_file(join_path(dir, trim(HISTORY_FILES(k))), ok)
      else
        call truncate_file(join_path(dir, trim(HISTORY_FILES(k))), int(bytes(k), i8), ok)
        if (.not. ok) call fatal_local('restart: cannot cut '// &
            join_path(dir, trim(HISTORY_FILES(k)))//' back to where the restart file left it')
      end if
    end do
  end subroutine history_restart_get

end module mefem_history_output
