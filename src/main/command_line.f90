!> The command line: `mefem [options] deck.k`.
module mefem_command_line
  use mefem_errors, only: say, fatal, terminate
  use mefem_model_summary, only: deck_stem
  implicit none
  private

  public :: parse_command_line, MEFEM_VERSION

  character(len=*), parameter :: MEFEM_VERSION = '0.1.0'

  !> What the user asked for.
  type, public :: run_options_t
    character(len=:), allocatable :: deck        !< main deck file
    character(len=:), allocatable :: output_dir  !< where results go
    logical :: check_only = .false.              !< read and validate only
  end type run_options_t

contains

  !> Read the arguments; -h and --version print and exit, mistakes stop with a message.
  subroutine parse_command_line(options)
    type(run_options_t), intent(out) :: options   !< the options
    integer :: i, n, length
    character(len=:), allocatable :: arg
    n = command_argument_count()
    i = 0
    do while (i < n)
      i = i + 1
      call get_command_argument(i, length=length)
      allocate(character(len=length) :: arg)
      call get_command_argument(i, arg)
      select case (arg)
      case ('-h', '--help')
        call print_usage()
        call terminate(0)
      case ('--version')
        call say('mefem '//MEFEM_VERSION)
        call terminate(0)
      case ('--check')
        options%check_only = .true.
      case ('-o', '--output')
        if (i == n) call fatal('option '//arg//' needs a directory')
        i = i + 1
        deallocate(arg)
        call get_command_argument(i, length=length)
        allocate(character(len=length) :: arg)
        call get_command_argument(i, arg)
        if (len_trim(arg) == 0) call fatal('option -o needs a directory, got an empty name')
        options%output_dir = arg
      case default
        if (arg(1:1) == '-' .and. len(arg) > 1) then
          call fatal('unknown option "'//arg//'" (mefem -h lists the options)')
        end if
        if (allocated(options%deck)) call fatal('two deck files given: "'//options%deck// &
            '" and "'//arg//'"')
        options%deck = arg
      end select
      deallocate(arg)
    end do
    if (.not. allocated(options%deck)) then
      call print_usage()
      call fatal('no deck file given')
    end if
    if (.not. allocated(options%output_dir)) options%output_dir = 'results/'//deck_stem(options%deck)
  end subroutine parse_command_line

  !> Print the usage text.
  subroutine print_usage()
    call say('usage: mefem [options] deck.k')
    call say('       mpirun -np N mefem [options] deck.k')
    call say('Reads an LS-DYNA keyword deck and runs the analysis it defines.')
    call say('options:')
    call say('  -o DIR, --output DIR  write results to DIR (default: results/<deck name>)')
    call say('  --check               read and validate the deck only; report every problem')
    call say('  -h, --help            this text')
    call say('  --version             print the version')
  end subroutine print_usage

end module mefem_command_line
