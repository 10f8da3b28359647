!> Deck parameters defined by *PARAMETER and referenced in fields as &name or -&name.
module mefem_parameters
  use mefem_strings, only: to_upper
  implicit none
  private

  public :: parameter_define, parameter_lookup, parameters_clear, split_parameter_spec

  integer, parameter, public :: PARAMETER_NAME_MAX = 32  !< longest parameter name

  !> One named parameter: its type letter and its value as text.
  type :: deck_parameter_t
    character(len=PARAMETER_NAME_MAX) :: name = ''
    character :: kind = 'R'                  !< R real, I integer, C character
    character(len=:), allocatable :: value   !< the value as written
  end type deck_parameter_t

  type(deck_parameter_t), allocatable :: table(:)
  integer :: n_defined = 0

contains

  !> Define (or redefine) a parameter.
  subroutine parameter_define(name, kind, value)
    character(len=*), intent(in) :: name    !< the name (case-insensitive)
    character, intent(in) :: kind           !< R, I or C
    character(len=*), intent(in) :: value   !< value text
    type(deck_parameter_t), allocatable :: grown(:)
    integer :: k
    k = find(name)
    if (k == 0) then
      if (.not. allocated(table)) allocate(table(32))
      if (n_defined == size(table)) then
        allocate(grown(2*size(table)))
        grown(1:n_defined) = table(1:n_defined)
        call move_alloc(grown, table)
      end if
      n_defined = n_defined + 1
      k = n_defined
      table(k)%name = to_upper(name)
    end if
    table(k)%kind = kind
    table(k)%value = trim(adjustl(value))
  end subroutine parameter_define

  !> Look a parameter up; found is false when it is not defined.
  subroutine parameter_lookup(name, value, found, kind)
    character(len=*), intent(in) :: name                   !< the name (case-insensitive)
    character(len=:), allocatable, intent(out) :: value    !< its value text
    logical, intent(out) :: found                          !< true when defined
    character, intent(out), optional :: kind               !< its type letter
    integer :: k
    k = find(name)
    found = k > 0
    if (found) then
      value = table(k)%value
      if (present(kind)) kind = table(k)%kind
    else
      value = ''
      if (present(kind)) kind = ' '
    end if
  end subroutine parameter_lookup

  !> Forget all parameters.
  subroutine parameters_clear()
    n_defined = 0
  end subroutine parameters_clear

  !> The type letter and the name of a PRMR field ('R tmax', 'Rtmax', 'i nid'): the first
  !> character is the type letter, the rest (blanks trimmed) the name. ok is false when the
  !> letter is not one of letters or the name is not a valid one (valid_parameter_name).
  pure subroutine split_parameter_spec(spec, letters, kind, name, ok)
    character(len=*), intent(in) :: spec                 !< the field, blanks trimmed
    character(len=*), intent(in) :: letters              !< type letters accepted ('RIC')
    character, intent(out) :: kind                       !< the type letter, upper case
    character(len=:), allocatable, intent(out) :: name   !< the name as written
    logical, intent(out) :: ok                           !< spec is 'letter name'
    kind = ' '
    name = ''
    ok = .false.
    if (len(spec) < 2) return
    if (index(to_upper(letters), to_upper(spec(1:1))) == 0) return
    kind = to_upper(spec(1:1))
    name = trim(adjustl(spec(2:)))
    ok = valid_parameter_name(name)
  end subroutine split_parameter_spec

  !> A parameter name: a letter, then letters, digits and '_', at most PARAMETER_NAME_MAX
  !> characters (longer names would be cut and meet others; other characters could not be
  !> read back inside an expression).
  pure logical function valid_parameter_name(name)
    character(len=*), intent(in) :: name                 !< the name as written
    character(len=*), parameter :: LETTERS = 'ABCDEFGHIJKLMNOPQRSTUVWXYZ'
    valid_parameter_name = .false.
    if (len(name) < 1 .or. len(name) > PARAMETER_NAME_MAX) return
    if (index(LETTERS, to_upper(name(1:1))) == 0) return
    valid_parameter_name = verify(to_upper(name), LETTERS//'0123456789_') == 0
  end function valid_parameter_name

  !> Index of a name in the table, 0 if absent.
  integer function find(name)
    character(len=*), intent(in) :: name   !< the name looked for
    integer :: k
    character(len=PARAMETER_NAME_MAX) :: key
    key = to_upper(adjustl(name))
    find = 0
    do k = 1, n_defined
      if (table(k)%name == key) then
        find = k
        return
      end if
    end do
  end function find

end module mefem_parameters
