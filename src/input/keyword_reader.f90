!> The keyword reader: reads a deck into the model, dispatching each keyword to its handler.
!>
!> The registry below lists every keyword mefem reads (its base name, the options it takes
!> and its handler), the keywords it skips with one warning (output requests and cosmetic
!> settings that cannot change the answer) and the rule for everything else: a keyword that
!> is not known is an error, because ignoring it could silently change the analysis.
!> A keyword name is matched against the longest registered base name; what follows it
!> (`_TITLE`, `_ID`, `_SET`, `_GENERATE` ...) are options, each checked against the list.
module mefem_keyword_reader
  use mefem_errors, only: input_error, input_error_count, warn_once
  use mefem_strings, only: to_upper, starts_with
  use mefem_deck_source, only: deck_open, deck_next_line, deck_close, location, &
                               LINE_KEYWORD, LINE_DATA, LINE_EOF
  use mefem_cards, only: reader_t, card_t, next_card, keyword_error
  use mefem_model, only: model_t
  use mefem_read_mesh, only: read_node, read_element_solid, read_element_shell, read_part, &
                             read_section_solid, read_section_shell
  use mefem_read_controls, only: read_keyword_card, read_title, read_parameter, &
                                 read_control_termination
  implicit none
  private

  public :: read_deck

  ! handler codes
  integer, parameter :: H_NODE = 1, H_ELEMENT_SOLID = 2, H_ELEMENT_SHELL = 3, H_PART = 4, &
                        H_SECTION_SOLID = 5, H_SECTION_SHELL = 6, H_KEYWORD = 7, H_TITLE = 8, &
                        H_PARAMETER = 9, H_CONTROL_TERMINATION = 10

  !> One registered keyword.
  type :: keyword_entry_t
    character(len=48) :: base = ''       !< name without options, upper case, no '*'
    integer :: handler = 0               !< H_* code
    character(len=64) :: options = ''    !< options accepted, as ' OPT1 OPT2 '
  end type keyword_entry_t

  integer, parameter :: N_ENTRIES = 10
  type(keyword_entry_t), parameter :: REGISTRY(N_ENTRIES) = [ &
    keyword_entry_t('NODE', H_NODE, ' '), &
    keyword_entry_t('ELEMENT_SOLID', H_ELEMENT_SOLID, ' '), &
    keyword_entry_t('ELEMENT_SHELL', H_ELEMENT_SHELL, ' '), &
    keyword_entry_t('PART', H_PART, ' '), &
    keyword_entry_t('SECTION_SOLID', H_SECTION_SOLID, ' TITLE '), &
    keyword_entry_t('SECTION_SHELL', H_SECTION_SHELL, ' TITLE '), &
    keyword_entry_t('KEYWORD', H_KEYWORD, ' '), &
    keyword_entry_t('TITLE', H_TITLE, ' '), &
    keyword_entry_t('PARAMETER', H_PARAMETER, ' '), &
    keyword_entry_t('CONTROL_TERMINATION', H_CONTROL_TERMINATION, ' ') ]

  !> Keyword names skipped with one warning: output and cosmetic settings.
  integer, parameter :: N_SKIPPED = 9
  character(len=32), parameter :: SKIPPED(N_SKIPPED) = [character(len=32) :: &
    'DATABASE_', 'CONTROL_OUTPUT', 'CONTROL_ENERGY', 'CONTROL_CPU', 'CONTROL_PARALLEL', &
    'CONTROL_MPP_', 'INTERFACE_SPRINGBACK', 'COMMENT', 'KEYWORD_ID']

contains

  !> Read the deck at path into model; returns the number of input errors found.
  subroutine read_deck(path, model, n_errors)
    character(len=*), intent(in) :: path     !< main deck file
    type(model_t), intent(inout) :: model    !< the model read
    integer, intent(out) :: n_errors         !< input errors found (0 = deck accepted)
    type(reader_t) :: rd
    logical :: ok, seen_keyword, data_reported
    integer :: n_keywords
    call deck_open(rd%deck, path, ok)
    if (.not. ok) then
      n_errors = input_error_count()
      return
    end if
    seen_keyword = .false.
    data_reported = .false.
    n_keywords = 0
    do
      call deck_next_line(rd%deck)
      if (rd%deck%kind == LINE_EOF) exit
      if (rd%deck%kind == LINE_DATA) then
        if (.not. data_reported) call input_error(location(rd%deck%file, rd%deck%line), &
            'data line outside any keyword: "'//trim(rd%deck%text(1:min(rd%deck%length, 40)))// &
            '" (is a *KEYWORD line missing above it?)')
        data_reported = .true.
        cycle
      end if
      if (rd%deck%kind /= LINE_KEYWORD) cycle
      data_reported = .false.
      n_keywords = n_keywords + 1
      call dispatch(rd, model, n_keywords == 1)
    end do
    if (n_keywords == 0) call input_error(path, &
        'the deck holds no keyword (an LS-DYNA keyword deck starts with *KEYWORD)')
    call deck_close(rd%deck)
    n_errors = input_error_count()
  end subroutine read_deck

  !> Identify the keyword on the current line and call its handler.
  subroutine dispatch(rd, model, first)
    type(reader_t), intent(inout) :: rd     !< reading state at a keyword line
    type(model_t), intent(inout) :: model   !< the model read
    logical, intent(in) :: first            !< this is the deck's first keyword
    character(len=:), allocatable :: line, name, rest, options, opt
    integer :: k, e, best, blank
    line = rd%deck%text(2:rd%deck%length)
    blank = scan(line, ' ,')
    if (blank == 0) then
      name = to_upper(line)
      rest = ''
    else
      name = to_upper(line(1:blank-1))
      rest = adjustl(line(blank+1:))
    end if
    ! format suffix: '+' long, '-' standard (attached to the name or as the next token)
    rd%long = rd%long_default
    if (len(name) > 1) then
      if (name(len(name):len(name)) == '+') then
        rd%long = .true.
        name = name(1:len(name)-1)
      else if (name(len(name):len(name)) == '-') then
        rd%long = .false.
        name = name(1:len(name)-1)
      end if
    end if
    if (len_trim(rest) > 0) then
      if (rest(1:1) == '+') rd%long = .true.
      if (rest(1:1) == '-') rd%long = .false.
    end if
    rd%keyword = '*'//name
    rd%kw_file = rd%deck%file
    rd%kw_line = rd%deck%line
    if (first .and. name /= 'KEYWORD') call keyword_error(rd, &
        'the deck must begin with *KEYWORD (only comments may precede it)')
    ! longest registered base name that the keyword starts with
    best = 0
    do e = 1, N_ENTRIES
      if (name == trim(REGISTRY(e)%base) .or. starts_with(name, trim(REGISTRY(e)%base)//'_')) then
        if (best == 0) then
          best = e
        else if (len_trim(REGISTRY(e)%base) > len_trim(REGISTRY(best)%base)) then
          best = e
        end if
      end if
    end do
    if (best == 0) then
      call skip_or_reject(rd, name)
      return
    end if
    ! options after the base name, each accepted by the entry
    options = ' '
    rest = name(len_trim(REGISTRY(best)%base)+2:)
    do while (len(rest) > 0)
      k = index(rest, '_')
      if (k == 0) then
        opt = rest
        rest = ''
      else
        opt = rest(1:k-1)
        rest = rest(k+1:)
      end if
      if (index(REGISTRY(best)%options, ' '//opt//' ') == 0) then
        call keyword_error(rd, 'option _'//opt//' of *'//trim(REGISTRY(best)%base)// &
            ' is not supported (accepted:'//trim(REGISTRY(best)%options)//')')
        call skip_cards(rd)
        return
      end if
      options = options//opt//' '
    end do
    select case (REGISTRY(best)%handler)
    case (H_NODE)
      call read_node(rd, model)
    case (H_ELEMENT_SOLID)
      call read_element_solid(rd, options, model)
    case (H_ELEMENT_SHELL)
      call read_element_shell(rd, options, model)
    case (H_PART)
      call read_part(rd, options, model)
    case (H_SECTION_SOLID)
      call read_section_solid(rd, options, model)
    case (H_SECTION_SHELL)
      call read_section_shell(rd, options, model)
    case (H_KEYWORD)
      call read_keyword_card(rd, line)
    case (H_TITLE)
      call read_title(rd, model)
    case (H_PARAMETER)
      call read_parameter(rd)
    case (H_CONTROL_TERMINATION)
      call read_control_termination(rd, model)
    end select
  end subroutine dispatch

  !> A keyword without handler: skip it with a warning if it is output or cosmetic,
  !> otherwise report it as an error (its cards are skipped either way).
  subroutine skip_or_reject(rd, name)
    type(reader_t), intent(inout) :: rd      !< reading state
    character(len=*), intent(in) :: name     !< keyword name, upper case, no '*'
    integer :: k
    do k = 1, N_SKIPPED
      if (starts_with(name, trim(SKIPPED(k)))) then
        call warn_once(name, '*'//name//' ignored (output or cosmetic setting not used '// &
            'by mefem), first at '//location(rd%kw_file, rd%kw_line))
        call skip_cards(rd)
        return
      end if
    end do
    call keyword_error(rd, 'keyword not supported by mefem; it could change the analysis, '// &
        'so it is not ignored (see doc/keywords.md for the supported keywords)')
    call skip_cards(rd)
  end subroutine skip_or_reject

  !> Skip the data cards of the current keyword.
  subroutine skip_cards(rd)
    type(reader_t), intent(inout) :: rd   !< reading state
    type(card_t) :: card
    logical :: got
    do
      call next_card(rd, card, got)
      if (.not. got) exit
    end do
  end subroutine skip_cards

end module mefem_keyword_reader
