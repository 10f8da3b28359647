!> Cards and fields of a keyword deck: column-exact fixed format, comma free format,
!> long format, &parameter substitution, and `file:line: *KEYWORD: message` errors.
!>
!> A keyword handler asks for its cards one by one (next_card), lays them out with the field
!> widths of that card (split_card; fixed columns unless the card holds a comma, 20-wide
!> fields in long format) and reads fields by position with get_int / get_real / get_text.
!> A bad field is reported with its name, columns and text, marks the card bad and yields the
!> default, so reading goes on and every problem of the deck is reported in one pass.
module mefem_cards
  use mefem_kinds, only: wp
  use mefem_errors, only: input_error, warn
  use mefem_strings, only: itoa, rtoa
  use mefem_numbers, only: parse_real, parse_int
  use mefem_parameters, only: parameter_lookup
  use mefem_deck_source, only: deck_t, deck_next_line, deck_push_back, location, MAX_LINE, &
                               LINE_KEYWORD, LINE_DATA, LINE_BLANK, LINE_EOF
  implicit none
  private

  integer, parameter, public :: MAX_FIELDS = 64   !< fields per card at most
  integer, parameter, public :: LONG_WIDTH = 20   !< field width in long format
  integer, parameter :: BLANK_CODE = 32            !< iachar(' ')

  public :: next_card, split_card, get_int, get_real, get_text, field_is_blank
  public :: card_where, card_error, card_warning, keyword_where, keyword_error

  !> The reading state handed to keyword handlers.
  type, public :: reader_t
    type(deck_t) :: deck                 !< the line source
    character(len=80) :: keyword = ''    !< current keyword as written, upper case ("*NODE")
    integer :: kw_file = 0               !< file index of the keyword line
    integer :: kw_line = 0               !< line number of the keyword line
    logical :: long = .false.            !< current keyword is in long (20-wide) format
    logical :: long_default = .false.    !< *KEYWORD LONG=Y given
  end type reader_t

  !> One data card with its field layout.
  type, public :: card_t
    character(len=MAX_LINE) :: text = ''     !< the line (valid in 1:length)
    integer :: length = 0                    !< characters in the line
    integer :: file = 0                      !< file index
    integer :: line = 0                      !< line number
    character(len=80) :: keyword = ''        !< keyword the card belongs to
    logical :: free = .false.                !< comma-separated card
    logical :: bad = .false.                 !< a field of this card was invalid
    logical :: unreadable = .false.          !< the card cannot be laid out: no field messages
    integer :: nfields = 0                   !< fields laid out
    integer :: first(MAX_FIELDS) = 1         !< first column of each field
    integer :: last(MAX_FIELDS) = 0          !< last column of each field (< first: empty)
    integer :: nominal_last(MAX_FIELDS) = 0  !< last column of each field's full width
  end type card_t

contains

  !> Next data card of the current keyword. got is false at the next keyword or the end of
  !> the deck. Blank lines are skipped unless keep_blank (then a blank card = all defaults).
  subroutine next_card(rd, card, got, keep_blank)
    type(reader_t), intent(inout) :: rd          !< reading state
    type(card_t), intent(inout) :: card          !< the card read
    logical, intent(out) :: got                  !< a card was read
    logical, intent(in), optional :: keep_blank  !< return blank lines as cards
    logical :: blank_is_card
    blank_is_card = .false.
    if (present(keep_blank)) blank_is_card = keep_blank
    got = .false.
    do
      call deck_next_line(rd%deck)
      select case (rd%deck%kind)
      case (LINE_KEYWORD)
        call deck_push_back(rd%deck)
        return
      case (LINE_EOF)
        return
      case (LINE_BLANK)
        if (.not. blank_is_card) cycle
      case (LINE_DATA)
      end select
      exit
    end do
    got = .true.
    card%length = rd%deck%length
    if (card%length > 0) card%text(1:card%length) = rd%deck%text(1:card%length)
    card%file = rd%deck%file
    card%line = rd%deck%line
    card%keyword = rd%keyword
    card%free = first_position(card%text(1:card%length), ',') > 0
    card%bad = .false.
    card%unreadable = .false.
    card%nfields = 0
  end subroutine next_card

  !> Lay the card out in fields of the given widths (standard format). In long format every
  !> field is LONG_WIDTH wide; a card holding a comma is split at the commas instead.
  subroutine split_card(rd, card, widths)
    type(reader_t), intent(in) :: rd       !< reading state (long format flag)
    type(card_t), intent(inout) :: card    !< the card
    integer, intent(in) :: widths(:)       !< standard widths of the fields
    integer :: i, col, w, k, tab
    card%nfields = min(size(widths), MAX_FIELDS)
    if (card%free) then
      col = 1
      do i = 1, card%nfields
        if (col > card%length) then
          card%first(i) = card%length + 1
          card%last(i) = card%length
        else
          k = index(card%text(col:card%length), ',')
          card%first(i) = col
          if (k == 0) then
            card%last(i) = card%length
            col = card%length + 1
          else
            card%last(i) = col + k - 2
            col = col + k
          end if
        end if
      end do
      do i = 1, card%length          ! tabs are blanks between commas
        if (card%text(i:i) == achar(9)) card%text(i:i) = ' '
      end do
      return
    end if
    tab = first_position(card%text(1:card%length), achar(9))
    if (tab > 0) then
      call input_error(card_where(card), 'tab character at column '//itoa(tab)// &
          ': fixed-format cards are read by columns; use blanks or commas')
      card%bad = .true.
      card%unreadable = .true.
    end if
    col = 1
    do i = 1, card%nfields
      w = widths(i)
      if (rd%long) w = LONG_WIDTH
      card%first(i) = col
      card%last(i) = min(col + w - 1, card%length)
      card%nominal_last(i) = col + w - 1
      col = col + w
    end do
  end subroutine split_card

  !> Position of the first occurrence of character c in s (0 if none): index(s, c) as a plain
  !> loop, several times faster than the library's general substring search.
  pure integer function first_position(s, c)
    character(len=*), intent(in) :: s   !< the text
    character, intent(in) :: c          !< the character looked for
    integer :: k, code
    code = iachar(c)
    first_position = 0
    do k = 1, len(s)
      if (iachar(s(k:k)) == code) then
        first_position = k
        return
      end if
    end do
  end function first_position

  !> Raw text of field i with blanks trimmed ('' when empty or beyond the card).
  function field_text(card, i) result(s)
    type(card_t), intent(in) :: card   !< the card
    integer, intent(in) :: i           !< field number
    character(len=:), allocatable :: s
    if (i > card%nfields) then
      s = ''
    else if (card%last(i) < card%first(i)) then
      s = ''
    else
      s = trim(adjustl(card%text(card%first(i):card%last(i))))
    end if
  end function field_text

  !> Columns lo:hi of field i without its leading and trailing blanks (hi < lo when the field
  !> is empty or beyond the card); the same text as field_text, without building a copy.
  pure subroutine field_bounds(card, i, lo, hi)
    type(card_t), intent(in) :: card   !< the card
    integer, intent(in) :: i           !< field number
    integer, intent(out) :: lo, hi     !< first and last non-blank column
    lo = 1
    hi = 0
    if (i > card%nfields) return
    lo = card%first(i)
    hi = card%last(i)
    do while (lo <= hi)
      if (iachar(card%text(lo:lo)) /= BLANK_CODE) exit
      lo = lo + 1
    end do
    do while (hi >= lo)
      if (iachar(card%text(hi:hi)) /= BLANK_CODE) exit
      hi = hi - 1
    end do
  end subroutine field_bounds

  !> True when the non-blank field text lo:hi holds a &parameter reference ('&name' or
  !> '-&name') that substitute would replace.
  pure logical function is_parameter_reference(card, lo, hi)
    type(card_t), intent(in) :: card   !< the card
    integer, intent(in) :: lo, hi      !< bounds from field_bounds (lo <= hi)
    is_parameter_reference = card%text(lo:lo) == '&'
    if (hi > lo) is_parameter_reference = is_parameter_reference .or. &
        card%text(lo:lo+1) == '-&'
  end function is_parameter_reference

  !> True when field i is empty (the deck asks for the default).
  logical function field_is_blank(card, i)
    type(card_t), intent(in) :: card   !< the card
    integer, intent(in) :: i           !< field number
    field_is_blank = len(field_text(card, i)) == 0
  end function field_is_blank

  !> Description of field i for messages: 'field NAME (columns a-b)' or '(entry i)'.
  function field_label(card, i, name) result(s)
    type(card_t), intent(in) :: card        !< the card
    integer, intent(in) :: i                !< field number
    character(len=*), intent(in) :: name    !< field name in the manual (trailing blanks
                                            !< are dropped)
    character(len=:), allocatable :: s
    if (card%free) then
      s = 'field '//trim(name)//' (entry '//itoa(i)//')'
    else
      s = 'field '//trim(name)//' (columns '//itoa(card%first(i))//'-'// &
          itoa(card%nominal_last(i))//')'
    end if
  end function field_label

  !> Field text with a &parameter replaced by its value; ok false (after a message) when the
  !> parameter is undefined.
  subroutine substitute(card, i, name, s, ok)
    type(card_t), intent(inout) :: card                !< the card
    integer, intent(in) :: i                           !< field number
    character(len=*), intent(in) :: name               !< field name
    character(len=:), allocatable, intent(inout) :: s  !< field text, replaced
    logical, intent(out) :: ok                         !< false if undefined
    character(len=:), allocatable :: value
    logical :: negate, found
    ok = .true.
    if (len(s) == 0) return
    negate = s(1:1) == '-'
    if (negate .and. len(s) > 1) then
      if (s(2:2) /= '&') return
    else if (s(1:1) /= '&') then
      return
    end if
    if (negate) then
      call parameter_lookup(s(3:), value, found)
    else
      call parameter_lookup(s(2:), value, found)
    end if
    if (.not. found) then
      call card_error(card, field_label(card, i, name)//': parameter "'//s// &
          '" is not defined (define it with *PARAMETER before its use)')
      card%bad = .true.
      ok = .false.
      return
    end if
    if (negate) then
      if (value(1:1) == '-') then
        s = value(2:)
      else
        s = '-'//value
      end if
    else
      s = value
    end if
  end subroutine substitute

  !> A field's text for a message, quoted: as written, and the parameter's value after it when
  !> the field is a parameter reference ('"&ph" (= "1.5")').
  function as_written(card, i, s) result(text)
    type(card_t), intent(in) :: card                   !< the card
    integer, intent(in) :: i                           !< field number
    character(len=*), intent(in) :: s                  !< the text after substitution
    character(len=:), allocatable :: text
    character(len=:), allocatable :: written
    written = field_text(card, i)
    if (written == s) then
      text = '"'//s//'"'
    else
      text = '"'//written//'" (= "'//s//'")'
    end if
  end function as_written

  !> Integer field i: blank gives default (or an error when required).
  subroutine get_int(card, i, name, value, default, required)
    type(card_t), intent(inout) :: card             !< the card
    integer, intent(in) :: i                        !< field number
    character(len=*), intent(in) :: name            !< field name for messages
    integer, intent(out) :: value                   !< the value read
    integer, intent(in), optional :: default        !< value of a blank field (default 0)
    logical, intent(in), optional :: required       !< a blank field is an error
    character(len=:), allocatable :: s
    logical :: ok
    integer :: lo, hi
    value = 0
    if (present(default)) value = default
    ! common case first, without copies: a plain number (else the general path below
    ! handles blanks, parameters and reports errors)
    call field_bounds(card, i, lo, hi)
    if (lo > hi .and. .not. present(required)) return     ! blank: the default
    if (lo <= hi) then
      if (.not. is_parameter_reference(card, lo, hi)) then
        call parse_int(card%text(lo:hi), value, ok)
        if (ok) return
        value = 0
        if (present(default)) value = default
      end if
    end if
    s = field_text(card, i)
    call substitute(card, i, name, s, ok)
    if (.not. ok) return
    if (len(s) == 0) then
      if (present(required)) then
        if (required) then
          call card_error(card, field_label(card, i, name)//' is required but blank')
          card%bad = .true.
        end if
      end if
      return
    end if
    call parse_int(s, value, ok)
    if (.not. ok) then
      call card_error(card, field_label(card, i, name)//': '//as_written(card, i, s)// &
                      ' is not an integer')
      card%bad = .true.
      value = 0
      if (present(default)) value = default
    end if
  end subroutine get_int

  !> Real field i: blank gives default (or an error when required).
  subroutine get_real(card, i, name, value, default, required)
    type(card_t), intent(inout) :: card             !< the card
    integer, intent(in) :: i                        !< field number
    character(len=*), intent(in) :: name            !< field name for messages
    real(wp), intent(out) :: value                  !< the value read
    real(wp), intent(in), optional :: default       !< value of a blank field (default 0)
    logical, intent(in), optional :: required       !< a blank field is an error
    character(len=:), allocatable :: s
    logical :: ok, overflow
    integer :: lo, hi
    value = 0.0_wp
    if (present(default)) value = default
    ! common case first, without copies: a plain number (else the general path below
    ! handles blanks, parameters and reports errors)
    call field_bounds(card, i, lo, hi)
    if (lo > hi .and. .not. present(required)) return     ! blank: the default
    if (lo <= hi) then
      if (.not. is_parameter_reference(card, lo, hi)) then
        call parse_real(card%text(lo:hi), value, ok)
        if (ok) return
        value = 0.0_wp
        if (present(default)) value = default
      end if
    end if
    s = field_text(card, i)
    call substitute(card, i, name, s, ok)
    if (.not. ok) return
    if (len(s) == 0) then
      if (present(required)) then
        if (required) then
          call card_error(card, field_label(card, i, name)//' is required but blank')
          card%bad = .true.
        end if
      end if
      return
    end if
    call parse_real(s, value, ok, overflow)
    if (overflow) then
      call card_error(card, field_label(card, i, name)//': '//as_written(card, i, s)// &
                      ' is beyond the largest number of double precision ('// &
                      rtoa(huge(1.0_wp))//')')
      card%bad = .true.
      value = 0.0_wp
      if (present(default)) value = default
    else if (.not. ok) then
      call card_error(card, field_label(card, i, name)//': '//as_written(card, i, s)// &
                      ' is not a number')
      card%bad = .true.
      value = 0.0_wp
      if (present(default)) value = default
    end if
  end subroutine get_real

  !> Text field i, blanks trimmed ('' when blank).
  subroutine get_text(card, i, value)
    type(card_t), intent(inout) :: card                 !< the card
    integer, intent(in) :: i                            !< field number
    character(len=:), allocatable, intent(out) :: value !< the text
    value = field_text(card, i)
  end subroutine get_text

  !> "file:line: *KEYWORD" of a card.
  function card_where(card) result(s)
    type(card_t), intent(in) :: card   !< the card
    character(len=:), allocatable :: s
    s = location(card%file, card%line)//': '//trim(card%keyword)
  end function card_where

  !> Report a problem of a card.
  subroutine card_error(card, message)
    type(card_t), intent(in) :: card         !< the card
    character(len=*), intent(in) :: message  !< what is wrong
    if (card%unreadable) return
    call input_error(card_where(card), message)
  end subroutine card_error

  !> A warning about a card ("file:line: *KEYWORD: message"): a field that is read but not
  !> used has a value that would change the analysis in LS-DYNA.
  subroutine card_warning(card, message)
    type(card_t), intent(in) :: card         !< the card
    character(len=*), intent(in) :: message  !< what is not used and what mefem does instead
    if (card%unreadable) return
    call warn(card_where(card)//': '//message)
  end subroutine card_warning

  !> "file:line: *KEYWORD" of the current keyword line.
  function keyword_where(rd) result(s)
    type(reader_t), intent(in) :: rd   !< reading state
    character(len=:), allocatable :: s
    s = location(rd%kw_file, rd%kw_line)//': '//trim(rd%keyword)
  end function keyword_where

  !> Report a problem of the current keyword as a whole (e.g. a missing card).
  subroutine keyword_error(rd, message)
    type(reader_t), intent(in) :: rd         !< reading state
    character(len=*), intent(in) :: message  !< what is wrong
    call input_error(keyword_where(rd), message)
  end subroutine keyword_error

end module mefem_cards
