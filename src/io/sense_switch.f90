!> LS-DYNA's sense switches for a running analysis: a file d3kil, written by the user into the
!> working directory or the output directory, asks the solver to stop (writing the state
!> reached), to print its status, or to write a result state now. The solvers call
!> sense_switch at points where all ranks are (every 100 explicit cycles, every implicit
!> step); its result is a set of the SENSE_ bits (iand to test them).
module mefem_sense_switch
  use mefem_comm, only: comm_is_root, comm_bcast
  use mefem_errors, only: warn
  use mefem_strings, only: to_lower, join_path
  use mefem_results, only: results_directory
  implicit none
  private

  public :: sense_switch, sense_switch_warn_leftover

  character(len=*), parameter :: SENSE_FILE = 'd3kil'  !< LS-DYNA's sense-switch file
  integer, parameter, public :: SENSE_NONE = 0     !< nothing asked
  integer, parameter, public :: SENSE_STOP = 1     !< sw1: stop, writing the state reached
  integer, parameter, public :: SENSE_STATUS = 2   !< sw2 (sw3): print the status
  integer, parameter, public :: SENSE_STATE = 4    !< sw4: write a result state now
  integer, parameter, public :: SENSE_RESTART = 8  !< sw3: write a restart file and go on

  logical :: warned_directory = .false.            !< said once that a d3kil is a directory
  logical :: warned_unreadable = .false.           !< said once that a d3kil cannot be read

contains

  !> LS-DYNA's sense switches, read from files d3kil in the working directory and in the output
  !> directory (rank 0 reads and deletes them and tells the others; collective). The result
  !> is a set of bits: SENSE_STOP (sw1, or an empty file: stop, writing the state reached and
  !> a restart file), SENSE_STATUS (sw2: print the cycle or step, time and step size),
  !> SENSE_RESTART (sw3: write a restart file and go on), SENSE_STATE (sw4: write a result
  !> state now and go on); one switch
  !> per line. Anything else, a d3kil that is a directory or cannot be read, is ignored with a
  !> warning.
  integer function sense_switch() result(action)
    integer :: k
    action = SENSE_NONE
    if (comm_is_root()) then
      do k = 1, 2
        action = ior(action, switches_in(sense_path(k)))
      end do
    end if
    call comm_bcast(action)
  end function sense_switch

  !> A warning at the start of an analysis when a d3kil file is there already (a leftover of
  !> an earlier run would stop this one at its first look).
  subroutine sense_switch_warn_leftover()
    integer :: k
    logical :: found, directory
    if (.not. comm_is_root()) return
    do k = 1, 2
      inquire(file=sense_path(k), exist=found)
      inquire(file=sense_path(k)//'/.', exist=directory)
      if (found .and. .not. directory) call warn('a file "'//sense_path(k)//'" is there at '// &
          'the start: the run will act on it (sense switches, README); delete it if an '// &
          'earlier run left it')
    end do
  end subroutine sense_switch_warn_leftover

  !> The k-th place looked at: the working directory (1), the output directory (2).
  function sense_path(k) result(path)
    integer, intent(in) :: k                  !< which place
    character(len=:), allocatable :: path
    if (k == 1) then
      path = SENSE_FILE
    else
      path = join_path(results_directory(), SENSE_FILE)
    end if
  end function sense_path

  !> The switches of the file at path (SENSE_NONE when there is none), which is deleted.
  integer function switches_in(path) result(action)
    character(len=*), intent(in) :: path      !< a d3kil path
    character(len=80) :: line
    character(len=256) :: message
    integer :: unit, ios, nline
    logical :: found, directory
    action = SENSE_NONE
    inquire(file=path, exist=found)
    if (.not. found) return
    inquire(file=path//'/.', exist=directory)
    if (directory) then
      if (.not. warned_directory) call warn('"'//path//'" is a directory, not a sense-switch '// &
          'file: ignored')
      warned_directory = .true.
      return
    end if
    open(newunit=unit, file=path, action='read', status='old', iostat=ios, iomsg=message)
    if (ios /= 0) then
      if (.not. warned_unreadable) call warn('"'//path//'" cannot be read: '//trim(message)// &
          '; ignored')
      warned_unreadable = .true.
      return
    end if
    nline = 0
    do
      read(unit, '(a)', iostat=ios) line
      if (ios /= 0) exit
      if (len_trim(line) == 0) cycle
      nline = nline + 1
      select case (trim(adjustl(to_lower(line))))
      case ('sw1')
        action = ior(action, SENSE_STOP)
      case ('sw2')
        action = ior(action, SENSE_STATUS)
      case ('sw3')
        action = ior(action, SENSE_RESTART)
      case ('sw4')
        action = ior(action, SENSE_STATE)
      case default
        call warn('d3kil: unknown switch "'//trim(adjustl(line))//'" ignored (sw1 stop, '// &
                  'sw2 status, sw3 restart file, sw4 write a state)')
      end select
    end do
    if (nline == 0) action = SENSE_STOP                  ! an empty file: LS-DYNA stops
    close(unit, status='delete', iostat=ios, iomsg=message)
    if (ios /= 0) call warn('"'//path//'" could not be deleted: '//trim(message))
  end function switches_in

end module mefem_sense_switch
