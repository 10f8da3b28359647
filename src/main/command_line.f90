!> The command line: `mefem [options] deck.k`, LS-DYNA's `i=deck.k` and `r=d3dump01` too.
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
    character(len=:), allocatable :: restart     !< restart file to continue from (r=)
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
        call next_argument('a directory')
        options%output_dir = arg
      case ('--restart')
        call next_argument('a restart file (d3dump01, runrsf)')
        options%restart = arg
      case default
        if (arg(1:1) == '-' .and. len(arg) > 1) then
          call fatal('unknown option "'//arg//'" (mefem -h lists the options)')
        end if
        if (len(arg) > 2) then                 ! LS-DYNA's i= (input) and r= (restart file)
          if (arg(1:2) == 'r=' .or. arg(1:2) == 'R=') then
            options%restart = arg(3:)
            deallocate(arg)
            cycle
          else if (arg(1:2) == 'i=' .or. arg(1:2) == 'I=') then
            arg = arg(3:)
          end if
        end if
        if (allocated(options%deck)) call fatal('two deck files given: "'//options%deck// &
            '" and "'//arg//'"')
        options%deck = arg
      end select
      deallocate(arg)
    end do
    if (allocated(options%restart)) then
      if (len(options%restart) == 0) call fatal('r= needs a restart file (d3dump01, runrsf)')
      return                     ! (the deck and output directory may come from the file)
    end if
    if (.not. allocated(options%deck)) then
      call print_usage()
      call fatal('no deck file given')
    end if
    if (.not. allocated(options%output_dir)) options%output_dir = 'results/'//deck_stem(options%deck)
  contains
    !> The option's value, the next argument, into arg.
    subroutine next_argument(what)
      character(len=*), intent(in) :: what            !< what it must be, for the message
      character(len=:), allocatable :: option
      option = arg
      if (i == n) call fatal('option '//option//' needs '//what)
      i = i + 1
      deallocate(arg)
      call get_command_argument(i, length=length)
      allocate(character(len=length) :: arg)
      call get_command_argument(i, arg)
      if (len_trim(arg) == 0) call fatal('option '//option//' needs '//what// &
                                         ', got an empty name')
    end subroutine next_argument
  end subroutine parse_command_line

  !> Print the usage text.
  subroutine print_usage()
    call say('usage: mefem [options] deck.k')
    call say('       mpirun -np N mefem [options] deck.k')
    call say('       mefem [options] r=RESTART_FILE [deck.k]')
    call say('Reads an LS-DYNA keyword deck and runs the analysis it defines.')
    call say('options:')
    call say('  -o DIR, --output DIR  write results to DIR (default: results/<deck name>)')
    call say('  --check               read and validate the deck only; report every problem')
    call say('  r=FILE, --restart FILE  continue the explicit run that wrote the restart file')
    call say('                        FILE (d3dump01, runrsf: *DATABASE_BINARY_D3DUMP, d3kil')
    call say('                        sw1/sw3, a stopping signal), on any number of ranks, with')
    call say('                        its deck and output directory unless given; i=deck.k is')
    call say('                        the deck, as LS-DYNA takes it')
    call say('  -h, --help            this text')
    call say('  --version             print the version')
  end subroutine print_usage

end module mefem_command_line
