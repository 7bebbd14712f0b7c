#include "catalogue/transaction.h"

#include "catalogue/catalogue_impl.hpp"

#include <stdexcept>

namespace hapstate {

Transaction::Transaction(Catalogue& catalogue) : catalogue_(&catalogue) {
  Catalogue::Impl& impl = *catalogue.impl_;
  if (impl.in_transaction) throw std::logic_error("Transaction: transactions do not nest");
  impl.db->exec("BEGIN IMMEDIATE");
  impl.in_transaction = true;
}

Transaction::~Transaction() {
  if (done_) return;
  Catalogue::Impl& impl = *catalogue_->impl_;
  sqlite3_exec(impl.db->get(), "ROLLBACK", nullptr, nullptr, nullptr);  // no throw from a dtor
  impl.in_transaction = false;
}

bool Catalogue::in_transaction() const { return impl_->in_transaction; }

void Transaction::commit() {
  if (done_) throw std::logic_error("Transaction::commit called twice");
  Catalogue::Impl& impl = *catalogue_->impl_;
  done_ = true;
  impl.in_transaction = false;
  try {
    impl.db->exec("COMMIT");
  } catch (...) {
    sqlite3_exec(impl.db->get(), "ROLLBACK", nullptr, nullptr, nullptr);
    throw;
  }
}

}  // namespace hapstate
