!> LS-DYNA's sense switches for a running analysis: a file d3kil, written by the user into the
!> working directory or the output directory, asks the solver to stop (writing the state
!> reached), to print its status, or to write a result state now. The solvers call
!> sense_switch at points where all ranks are (every SENSE_INTERVAL cycles, every step).
module mefem_sense_switch
  use mefem_comm, only: comm_is_root, comm_bcast
  use mefem_errors, only: warn
  use mefem_strings, only: to_lower, join_path
  use mefem_results, only: results_directory
  implicit none
  private

  public :: sense_switch

  character(len=*), parameter :: SENSE_FILE = 'd3kil'  !< LS-DYNA's sense-switch file
  integer, parameter, public :: SENSE_NONE = 0     !< nothing asked
  integer, parameter, public :: SENSE_STOP = 1     !< sw1: stop, writing the state reached
  integer, parameter, public :: SENSE_STATUS = 2   !< sw2 (sw3): print the status
  integer, parameter, public :: SENSE_STATE = 4    !< sw4: write a result state now

contains

  !> LS-DYNA's sense switches, read from a file d3kil in the working directory or in the output
  !> directory (rank 0 looks, deletes the file and tells the others; collective): sw1 or an
  !> empty file = stop, writing the state reached (SENSE_STOP); sw2 = print the cycle, time
  !> and step (SENSE_STATUS); sw3 = the same (mefem writes no restart files); sw4 = write a
  !> result state now and go on (SENSE_STATE). Anything else is ignored with a warning.
  integer function sense_switch() result(action)
    character(len=:), allocatable :: path
    character(len=80) :: line
    integer :: k, unit, ios
    logical :: found
    action = SENSE_NONE
    if (comm_is_root()) then
      do k = 1, 2
        if (k == 1) then
          path = SENSE_FILE
        else
          path = join_path(results_directory(), SENSE_FILE)
        end if
        inquire(file=path, exist=found)
        if (found) exit
      end do
      if (found) then
        line = ''
        open(newunit=unit, file=path, action='read', status='old', iostat=ios)
        if (ios == 0) then
          read(unit, '(a)', iostat=ios) line
          if (ios /= 0) line = ''
          close(unit, status='delete')
        end if
        select case (trim(adjustl(to_lower(line))))
        case ('', 'sw1')
          action = SENSE_STOP
        case ('sw2')
          action = SENSE_STATUS
        case ('sw3')
          action = SENSE_STATUS
          call warn('d3kil (sw3): mefem writes no restart files; the status follows')
        case ('sw4')
          action = SENSE_STATE
        case default
          call warn('d3kil: unknown switch "'//trim(adjustl(line))//'" ignored (sw1 stop, '// &
                    'sw2 status, sw4 write a state)')
        end select
      end if
    end if
    call comm_bcast(action)
  end function sense_switch

end module mefem_sense_switch
