!> Keyword handlers for deck-level and control keywords: *KEYWORD, *TITLE, *PARAMETER,
!> *CONTROL_* and *DATABASE_* output requests, and mefem's own *MEFEM_* keywords.
module mefem_read_controls
  use mefem_kinds, only: wp
  use mefem_strings, only: to_upper, itoa
  use mefem_parameters, only: parameter_define
  use mefem_numbers, only: parse_real, parse_int
  use mefem_cards, only: reader_t, card_t, next_card, split_card, get_int, get_real, get_text, &
                         card_error, keyword_error
  use mefem_model, only: model_t
  implicit none
  private

  public :: read_keyword_card, read_title, read_parameter, read_control_termination

  integer, parameter :: W_10(8) = 10   !< standard 8 x 10 card

contains

  !> *KEYWORD [memory] [LONG=Y|S|N] [I10=Y]: sets the deck's default field format.
  subroutine read_keyword_card(rd, line)
    type(reader_t), intent(inout) :: rd      !< reading state
    character(len=*), intent(in) :: line     !< keyword line without the '*'
    character(len=:), allocatable :: upper
    integer :: k
    type(card_t) :: card
    logical :: got
    upper = to_upper(line)
    k = index(upper, 'LONG=')
    if (k > 0 .and. k + 5 <= len(upper)) then
      select case (upper(k+5:k+5))
      case ('Y')
        rd%long_default = .true.
      case ('N', 'S')
        rd%long_default = .false.
      case default
        call keyword_error(rd, 'LONG= must be Y, S or N')
      end select
    end if
    if (index(upper, 'I10=Y') > 0) call keyword_error(rd, &
        'I10=Y (10-digit labels) is not supported; write the deck in LONG=Y format')
    do   ! *KEYWORD takes no cards; anything after it belongs to nobody
      call next_card(rd, card, got)
      if (.not. got) exit
      call card_error(card, 'unexpected data card after *KEYWORD')
    end do
  end subroutine read_keyword_card

  !> *TITLE: one card, the job title.
  subroutine read_title(rd, model)
    type(reader_t), intent(inout) :: rd      !< reading state
    type(model_t), intent(inout) :: model    !< model receiving the title
    type(card_t) :: card
    logical :: got
    call next_card(rd, card, got, keep_blank=.true.)
    if (got) model%controls%title = card%text(1:min(card%length, 80))
  end subroutine read_title

  !> *PARAMETER: up to four (type+name, value) pairs per card, 10 columns each:
  !> 'R name' real, 'I name' integer, 'C name' character. The value is checked by type.
  subroutine read_parameter(rd)
    type(reader_t), intent(inout) :: rd      !< reading state
    type(card_t) :: card
    logical :: got, ok
    integer :: pair, ivalue
    real(wp) :: rvalue
    character(len=:), allocatable :: spec, value, name
    character :: kind
    do
      call next_card(rd, card, got)
      if (.not. got) exit
      call split_card(rd, card, W_10)
      do pair = 1, 4
        call get_text(card, 2*pair - 1, spec)
        call get_text(card, 2*pair, value)
        if (len(spec) == 0 .and. len(value) == 0) cycle
        kind = 'R'
        name = spec
        if (len(spec) > 2) then
          if (index('RICricn', spec(1:1)) > 0 .and. spec(2:2) == ' ') then
            kind = to_upper(spec(1:1))
            name = trim(adjustl(spec(3:)))
          end if
        end if
        if (len(name) == 0 .or. scan(name, ' &') > 0) then
          call card_error(card, 'parameter '//itoa(pair)//': "'//spec// &
              '" is not "R name", "I name" or "C name"')
          cycle
        end if
        ok = .true.
        if (kind == 'R') call parse_real(value, rvalue, ok)
        if (kind == 'I') call parse_int(value, ivalue, ok)
        if (.not. ok .or. (kind /= 'C' .and. len(value) == 0)) then
          call card_error(card, 'parameter '//name//': value "'//value// &
              '" is not a valid '//merge('real   ', 'integer', kind == 'R'))
          cycle
        end if
        call parameter_define(name, kind, value)
      end do
    end do
  end subroutine read_parameter

  !> *CONTROL_TERMINATION: ENDTIM ENDCYC DTMIN ENDENG ENDMAS.
  subroutine read_control_termination(rd, model)
    type(reader_t), intent(inout) :: rd      !< reading state
    type(model_t), intent(inout) :: model    !< model receiving the controls
    type(card_t) :: card
    logical :: got
    call next_card(rd, card, got, keep_blank=.true.)
    if (.not. got) then
      call keyword_error(rd, 'missing card 1 (ENDTIM ENDCYC DTMIN ENDENG ENDMAS)')
      return
    end if
    call split_card(rd, card, W_10)
    associate (c => model%controls)
      call get_real(card, 1, 'ENDTIM', c%end_time)
      call get_int(card, 2, 'ENDCYC', c%end_cycle)
      call get_real(card, 3, 'DTMIN', c%dt_min_fraction)
      call get_real(card, 4, 'ENDENG', c%end_energy)
      call get_real(card, 5, 'ENDMAS', c%end_mass, default=1.0e8_wp)
      if (c%end_time < 0.0_wp) call card_error(card, 'field ENDTIM must not be negative')
      if (c%end_cycle < 0) call card_error(card, 'field ENDCYC must not be negative')
      if (c%end_time == 0.0_wp .and. c%end_cycle == 0) call card_error(card, &
          'field ENDTIM: the termination time must be positive (or give ENDCYC)')
      c%have_termination = .true.
    end associate
  end subroutine read_control_termination

end module mefem_read_controls
