!> Small card-reading helpers shared by the keyword handlers: the title card of a _TITLE
!> option, the ID/HEADING card of an _ID option, and the end of a keyword that takes a
!> fixed number of cards.
module mefem_card_helpers
  use mefem_kinds, only: wp
  use mefem_strings, only: itoa, rtoa
  use mefem_cards, only: reader_t, card_t, next_card, split_card, get_int, card_error, &
                         keyword_error
  implicit none
  private

  public :: has_option, read_title_card, read_id_card, reject_extra_cards, skip_extra_cards
  public :: read_id_option
  public :: quoted_real

  integer, parameter :: W_ID(2) = [10, 70]   !< ID/HEADING card: I10 A70

contains

  !> True when the keyword's option list holds option (e.g. 'TITLE').
  pure logical function has_option(options, option)
    character(len=*), intent(in) :: options   !< options as ' OPT1 OPT2 '
    character(len=*), intent(in) :: option    !< the option looked for
    has_option = index(options, ' '//option//' ') > 0
  end function has_option

  !> The title card of a _TITLE option (80 characters; may be blank). title is '' when the
  !> option is not given; a missing card is reported.
  subroutine read_title_card(rd, options, title)
    type(reader_t), intent(inout) :: rd           !< reading state
    character(len=*), intent(in) :: options       !< keyword options
    character(len=*), intent(out) :: title        !< the title text
    type(card_t) :: card
    logical :: got
    title = ''
    if (.not. has_option(options, 'TITLE')) return
    call next_card(rd, card, got, keep_blank=.true.)
    if (.not. got) then
      call keyword_error(rd, 'missing the title card of the _TITLE option')
      return
    end if
    title = adjustl(card%text(1:min(card%length, 80)))
  end subroutine read_title_card

  !> The ID/HEADING card of an _ID option (ID I10, HEADING A70). ok is false when the card
  !> is missing or its ID is not an integer (then the keyword is not read further).
  subroutine read_id_card(rd, id, heading, ok)
    type(reader_t), intent(inout) :: rd           !< reading state
    integer, intent(out) :: id                    !< the ID field
    character(len=*), intent(out) :: heading      !< the HEADING field
    logical, intent(out) :: ok                    !< the card was read correctly
    type(card_t) :: card
    logical :: got
    id = 0
    heading = ''
    ok = .false.
    call next_card(rd, card, got, keep_blank=.true.)
    if (.not. got) then
      call keyword_error(rd, 'missing the ID/HEADING card of the _ID option')
      return
    end if
    call split_card(rd, card, W_ID)
    call get_int(card, 1, 'ID', id)
    if (card%nfields >= 2 .and. card%last(2) >= card%first(2)) &
      heading = adjustl(card%text(card%first(2):card%last(2)))
    if (card%bad) return
    if (id < 0) then
      call card_error(card, 'field ID must not be negative (got '//itoa(id)//')')
      return
    end if
    ok = .true.
  end subroutine read_id_card

  !> Report every further data card of a keyword that takes no more (what names the object
  !> defined, e.g. 'material 3').
  subroutine reject_extra_cards(rd, what)
    type(reader_t), intent(inout) :: rd           !< reading state
    character(len=*), intent(in) :: what          !< the object the keyword defines
    type(card_t) :: card
    logical :: got, reported
    reported = .false.
    do
      call next_card(rd, card, got)
      if (.not. got) exit
      if (.not. reported) call card_error(card, 'unexpected data card after the cards of '// &
          what//' (one definition per keyword; repeat the keyword line for the next one)')
      reported = .true.
    end do
  end subroutine reject_extra_cards

  !> Skip the remaining data cards of the current keyword (optional cards mefem ignores).
  !> The _ID option's card, when the keyword has that option: ok is false (and the keyword's
  !> cards are skipped) when the card is missing or bad.
  subroutine read_id_option(rd, options, id, heading, ok)
    type(reader_t), intent(inout) :: rd             !< reading state
    character(len=*), intent(in) :: options         !< keyword options
    integer, intent(inout) :: id                    !< the ID (unchanged without the option)
    character(len=*), intent(inout) :: heading      !< the heading
    logical, intent(out) :: ok                      !< reading may go on
    ok = .true.
    if (.not. has_option(options, 'ID')) return
    call read_id_card(rd, id, heading, ok)
    if (.not. ok) call skip_extra_cards(rd)
  end subroutine read_id_option

  subroutine skip_extra_cards(rd)
    type(reader_t), intent(inout) :: rd           !< reading state
    type(card_t) :: card
    logical :: got
    do
      call next_card(rd, card, got)
      if (.not. got) exit
    end do
  end subroutine skip_extra_cards

  !> '(got x)' text for messages.
  function quoted_real(x) result(s)
    real(wp), intent(in) :: x   !< the value
    character(len=:), allocatable :: s
    s = '(got '//rtoa(x)//')'
  end function quoted_real

end module mefem_card_helpers
